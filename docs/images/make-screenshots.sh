#!/usr/bin/env bash
# The manual's pictures, made by the app itself (`parol6 screenshot --ui`: the whole window, rendered
# offscreen, after scripted states), so they show what the program shows. Run from anywhere:
#   bash docs/images/make-screenshots.sh            # builds the release binary first
#   PAROL6=/path/to/parol6 bash docs/images/make-screenshots.sh
# Each picture's JSON report (the run's length, the longest frame) is printed.
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ -z "${PAROL6:-}" ]; then
    cargo build --release -q -p parol6-app
    PAROL6="${CARGO_TARGET_DIR:-target}/release/parol6"
fi
out=docs/images
# the window at start: the simulation at standby
"$PAROL6" screenshot --ui --size 1280x800 "$out/window.png"
# the smallest supported window
"$PAROL6" screenshot --ui --size 1024x700 "$out/window-1024x700.png"
# a program run in the simulation, with the joint positions plotted
"$PAROL6" screenshot --ui --size 1280x800 --run draw --plot position "$out/window-program-plots.png"
# the same kind of run on the controller (the built-in emulator): tracking error, commanded - measured
"$PAROL6" screenshot --ui --size 1280x800 --run draw --plot cmd-meas "$out/cmd-meas-simulation.png"
"$PAROL6" screenshot --ui --size 1280x800 --fake-robot --run draw --plot cmd-meas "$out/cmd-meas-robot.png"
"$PAROL6" screenshot --ui --size 1280x800 --fake-robot --run "pick & place" --plot velocity "$out/window-robot.png"
