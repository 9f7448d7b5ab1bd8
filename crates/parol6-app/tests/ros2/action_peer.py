#!/usr/bin/env python3
"""An independent rmw_zenoh action client for `parol6 serve --ros2` (run by tests/ros2_action.rs).

Speaks control_msgs/action/FollowJointTrajectory the way rmw_zenoh carries an action: Zenoh
queries (`session.get`) on the key expressions of the services `<name>/_action/send_goal`,
`get_result` and `cancel_goal`, each with rmw_zenoh's attachment (sequence number, time stamp,
16-byte GID), and a subscription to `<name>/_action/status`. Its CDR is its own (the struct
module, through tests/ros2/peer.py's reader and writer); the type hashes are literals copied
from the rosidl-generated C headers (control_msgs `follow_joint_trajectory__struct.h`,
action_msgs `cancel_goal__struct.h`, `goal_status_array__struct.h`), not from our code. On
loopback only (listen tcp/127.0.0.1:PORT, multicast off). It checks:

- the liveliness tokens: three `SS` (service server) tokens and two `MP` (feedback, status);
- with --remote: hostile goals (malformed CDR, wrong joint names, NaN, out of limits, times not
  increasing, a multi-DOF trajectory, an old header stamp, a tolerance for an unknown joint)
  rejected, get_result telling the error code, and no motion; a valid goal accepted, its
  result SUCCEEDED with error code 0 and the published joint states ending at its last point;
  a slow goal cancelled while it runs (CANCELED, the arm stops short of it);
- without --remote: a valid goal rejected, its result naming --allow-remote-control, no motion.

Prints one JSON line and exits 0, or the failure and exits 1.
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer  # noqa: E402  (its CDR reader / writer, type hashes of the plain messages, helpers)
import zenoh  # noqa: E402
import zenoh.ext as ze  # noqa: E402

from peer import Reader, Writer, check, wait_for  # noqa: E402

ACTION = "/parol6_arm_controller/follow_joint_trajectory"
# (DDS type name, RIHS01 hash from the generated headers' TYPE_VERSION_HASH__INIT bytes)
SEND_GOAL = ("control_msgs::action::dds_::FollowJointTrajectory_SendGoal_",
             "RIHS01_4915b9909747df962256f0fe9a7dc832ba6e7ec2c5e827c5ba239b7b451d52aa")
GET_RESULT = ("control_msgs::action::dds_::FollowJointTrajectory_GetResult_",
              "RIHS01_a42b878fc686578b092e626c27ba796dab419d9d5f3275920e4eca7769062539")
CANCEL_GOAL = ("action_msgs::srv::dds_::CancelGoal_",
               "RIHS01_6a5f062d4e445bb8f6dfeb28d8ba83845efc58238741896b43c9dc8e1cffb775")
FEEDBACK = ("control_msgs::action::dds_::FollowJointTrajectory_FeedbackMessage_",
            "RIHS01_88e16acd364ad5bc90b661a4f77fec9ab40874e8eeaaf4673e9cd78e41038b99")
STATUS = ("action_msgs::msg::dds_::GoalStatusArray_",
          "RIHS01_ffe5f95b22109dd7ef2199ccf443f5b6be19c157618c8fc12f4d9a2b5fc6c4dc")
NAMES = ("J1", "J2", "J3", "J4", "J5", "J6")
# path tolerances: one the simulation's tracking lag stays well within, one it exceeds
PATH_TOLERANCE_OK_RAD = 0.05
PATH_TOLERANCE_TIGHT_RAD = 1e-4
# a velocity path tolerance any tracking exceeds while the arm speeds up
PATH_VELOCITY_TOLERANCE_TIGHT_RAD_S = 1e-6
GOAL_TIME_TOLERANCE_S = 0.3
SUCCEEDED, CANCELED, ABORTED = 4, 5, 6
GID = bytes(range(100, 116))


def skey(sub, ty, domain=0):
    return f"{domain}/{ACTION.strip('/')}/_action/{sub}/{ty[0]}/{ty[1]}"


def goal_request(uuid, points, names=NAMES, stamp=(0, 0), multi_dof=False, tolerance=None, path_tolerance=None,
                 goal_time=0.0):
    """SendGoal request: UUID, then FollowJointTrajectory_Goal field by field."""
    w = Writer()
    w.b += uuid
    w.i32(stamp[0])
    w.u32(stamp[1])
    w.string("")
    w.u32(len(names))
    for n in names:
        w.string(n)
    w.u32(len(points))
    for q, t in points:
        w.u32(len(q))
        for v in q:
            w.f64(v)
        for _ in range(3):
            w.u32(0)
        w.i32(int(t))
        w.u32(int(round((t - int(t)) * 1e9)))
    # multi_dof_trajectory: header, joint_names, points
    w.i32(0)
    w.u32(0)
    w.string("")
    w.u32(1 if multi_dof else 0)
    if multi_dof:
        w.string("base_planar")
    w.u32(0)
    tolerances(w, path_tolerance or [])  # path_tolerance
    w.u32(0)  # component_path_tolerance
    tolerances(w, tolerance or [])  # goal_tolerance
    w.u32(0)  # component_goal_tolerance
    w.i32(int(goal_time))  # goal_time_tolerance
    w.u32(int(round((goal_time - int(goal_time)) * 1e9)))
    return w.payload()


def tolerances(w, tol):
    """control_msgs/msg/JointTolerance[]: name, position, velocity, acceleration; `tol` holds
    (name, position) or (name, position, velocity)."""
    w.u32(len(tol))
    for name, pos, *vel in tol:
        w.string(name)
        w.f64(pos)
        w.f64(vel[0] if vel else 0.0)
        w.f64(0.0)


def feedback_message(payload):
    """FollowJointTrajectory_FeedbackMessage (Jazzy's control_msgs): goal_id, then the feedback:
    header, joint_names, desired / actual / error JointTrajectoryPoint, multi_dof_joint_names and
    three MultiDOFJointTrajectoryPoint. Every byte must be read."""
    r = Reader(payload)
    uuid = bytes(r.b[:16])
    r.o = 16

    def point():
        return {"positions": r.seq(r.f64), "velocities": r.seq(r.f64), "accelerations": r.seq(r.f64),
                "effort": r.seq(r.f64), "time_from_start": r.i32() + r.u32() * 1e-9}

    def multi_dof_point():
        return {"transforms": r.seq(lambda: [r.f64() for _ in range(7)]),
                "velocities": r.seq(lambda: [r.f64() for _ in range(6)]),
                "accelerations": r.seq(lambda: [r.f64() for _ in range(6)]),
                "time_from_start": (r.i32(), r.u32())}

    h = r.header()
    msg = {"goal_id": uuid, "stamp": (h["sec"], h["nanosec"]), "joint_names": r.seq(r.string),
           "desired": point(), "actual": point(), "error": point(), "multi_dof_joint_names": r.seq(r.string),
           "multi_dof": [multi_dof_point() for _ in range(3)]}
    check(r.o == len(r.b), f"the feedback message ends at byte {r.o} of {len(r.b)}")
    return msg


def check_feedback(fb, js_by_stamp, last):
    """The goal's feedback: 20 Hz on the motion clock, actual = the joint state published with the
    same stamp, error = desired - actual, desired on the way from the first desired position to
    `last`. The largest |error| of J1, rad."""
    check(len(fb) >= 10, f"feedback while the goal ran: {len(fb)} messages")
    first = fb[0]["desired"]["positions"]
    times = [m["desired"]["time_from_start"] for m in fb]
    steps = [round(b - a, 6) for a, b in zip(times, times[1:])]
    # 20 Hz on the motion clock: every step 0.05 s, but for a step next to a sample the starved
    # simulation thread published late (it publishes once per wake-up: on a loaded 2-core host,
    # with the Foxglove server's threads beside it, a wake-up can cover 10 ms of steps)
    exact = sum(1 for s in steps if s == 0.05)
    check(exact >= len(steps) - 3 and all(0.035 <= s <= 0.065 for s in steps),
          f"feedback every 0.05 s of the goal: {steps}")
    matched = 0
    for m in fb:
        check(m["joint_names"] == list(NAMES) and m["multi_dof_joint_names"] == [], f"joints: {m['joint_names']}")
        check(all(not any(p[k] for k in ("transforms", "velocities", "accelerations")) and p["time_from_start"] == (0, 0)
                  for p in m["multi_dof"]), "the multi-DOF points are empty")
        d, a, e = m["desired"]["positions"], m["actual"]["positions"], m["error"]["positions"]
        check(all(abs(e[j] - (d[j] - a[j])) < 1e-12 for j in range(6)), f"error = desired - actual: {m}")
        check(all(min(first[j], last[j]) - 1e-6 <= d[j] <= max(first[j], last[j]) + 1e-6 for j in range(6)),
              f"desired {d} between {first} and {last}")
        if m["stamp"] in js_by_stamp:
            check(js_by_stamp[m["stamp"]] == a, f"actual = /joint_states of the same stamp: {a} {js_by_stamp[m['stamp']]}")
            matched += 1
    check(matched >= len(fb) - 1, f"{matched} of {len(fb)} feedback stamps are /joint_states stamps")
    desired = [m["desired"]["positions"][0] for m in fb]
    sign = 1 if last[0] >= first[0] else -1
    check(all(sign * (b - a) >= -1e-9 for a, b in zip(desired, desired[1:])), "desired J1 moves one way")
    return max(abs(m["error"]["positions"][0]) for m in fb)


def uuid_of(n):
    return bytes([n]) * 16


class EventReader:
    """`/events` as the Foxglove client (`tests/peers/foxglove_client.py events`) prints them."""

    def __init__(self):
        self.proc = None
        self.lines = []
        self.lock = threading.Lock()

    def start(self, url):
        client = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "peers", "foxglove_client.py")
        self.proc = subprocess.Popen([sys.executable, client, "events", url, "120"], stdout=subprocess.PIPE, text=True)
        subscribed = json.loads(self.proc.stdout.readline() or "null")
        check(subscribed == {"subscribed": "/events"}, f"the Foxglove client subscribed to /events: {subscribed}")

        def read():
            for line in self.proc.stdout:
                with self.lock:
                    self.lines.append(json.loads(line))

        threading.Thread(target=read, daemon=True).start()

    def wait_for(self, needles, seconds):
        """The first event message containing all of `needles`, within `seconds`."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            with self.lock:
                for e in self.lines:
                    if all(n in (e.get("message") or "") for n in needles):
                        return e["message"]
            time.sleep(0.05)
        with self.lock:
            seen = [e.get("message") for e in self.lines]
        raise peer.Failure(f"no /events message with {needles} within {seconds} s; seen: {seen}")

    def stop(self):
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(timeout=10)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", required=True)
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--remote", action="store_true")
    ap.add_argument("--tolerance", action="store_true", help="with --remote: the tolerance goals, not the hostile ones")
    ap.add_argument("--events", action="store_true",
                    help="also serve Foxglove and read /events back with tests/peers/foxglove_client.py")
    args = ap.parse_args()

    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("listen/endpoints", json.dumps([f"tcp/127.0.0.1:{args.port}"]))
    conf.insert_json5("connect/endpoints", "[]")
    conf.insert_json5("scouting/multicast/enabled", "false")
    session = zenoh.open(conf)
    lock = threading.Lock()
    got = {"js": [], "status": [], "js_by_stamp": {}, "feedback": []}

    def on_js(sample):
        msg = peer.joint_state(bytes(sample.payload.to_bytes()))
        with lock:
            got["js"].append(msg["position"])
            got["js_by_stamp"][(msg["header"]["sec"], msg["header"]["nanosec"])] = msg["position"]

    def on_feedback(sample):
        try:
            msg = feedback_message(bytes(sample.payload.to_bytes()))
        except Exception as e:  # noqa: BLE001  (reported, not raised in Zenoh's thread)
            msg = {"decode_error": repr(e)}
        with lock:
            got["feedback"].append(msg)

    def on_status(sample):
        r = Reader(bytes(sample.payload.to_bytes()))
        items = []
        for _ in range(r.u32()):
            uuid = bytes(r.b[r.o:r.o + 16])
            r.o += 16
            r.i32()
            r.u32()
            status = r.b[r.o]
            r.o += 1
            items.append((uuid, status))
        with lock:
            got["status"].append(items)

    subs = [session.declare_subscriber(peer.key("/joint_states", "sensor_msgs/msg/JointState"), on_js),
            session.declare_subscriber(skey("status", STATUS), on_status),
            session.declare_subscriber(skey("feedback", FEEDBACK), on_feedback)]
    seq = [0]

    def call(sub, ty, payload):
        seq[0] += 1
        n = seq[0]
        att = ze.z_serialize((ze.Int64(n), ze.Int64(time.time_ns()), GID))
        replies = list(session.get(skey(sub, ty), payload=payload, attachment=att, timeout=20.0))
        oks = [r.ok for r in replies if r.ok is not None]
        check(len(oks) == 1, f"one reply to {sub} request {n}: {replies}")
        a = ze.z_deserialize(tuple[ze.Int64, ze.Int64, bytes], oks[0].attachment)
        check(a[0] == n and a[2] == GID, f"the reply carries our sequence number and GID: {a}")
        return Reader(bytes(oks[0].payload.to_bytes()))

    def send_goal(payload):
        r = call("send_goal", SEND_GOAL, payload)
        accepted = r.b[0]
        r.o = 1
        return accepted == 1, (r.i32(), r.u32())

    def get_result(uuid):
        r = call("get_result", GET_RESULT, b"\x00\x01\x00\x00" + uuid)
        status = r.b[0]
        r.o = 1
        return status, r.i32(), r.string()

    def j1_half_a_second_apart():
        """J1 from /joint_states 0.5 s and 1.0 s from now: equal when the arm has stopped."""
        samples = []
        for _ in range(2):
            time.sleep(0.5)
            with lock:
                samples.append(got["js"][-1][0])
        return samples[0], samples[1]

    cmd = [args.exe, "serve", "--ros2", "--ros2-connect", f"tcp/127.0.0.1:{args.port}", "--seconds", "90"]
    if args.remote:
        cmd.append("--allow-remote-control")
    if args.events:
        cmd += ["--foxglove", "127.0.0.1:0"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    report = {"command": " ".join(cmd[1:])}
    events = EventReader()
    try:
        first = json.loads(proc.stdout.readline() or "null")
        check(first and "ros2" in first.get("listening", {}), f"the first line names the ros2 server: {first}")
        if args.events:
            events.start(first["listening"]["foxglove"])
        wait_for(lambda: len(got["js"]) >= 20, 20, "joint states")

        tokens = [str(r.ok.key_expr) for r in session.liveliness().get("@ros2_lv/0/**", timeout=5.0) if r.ok]
        mangled = ACTION.replace("/", "%") + "%_action%"
        want = [("SS", "send_goal", SEND_GOAL), ("SS", "get_result", GET_RESULT), ("SS", "cancel_goal", CANCEL_GOAL),
                ("MP", "feedback", FEEDBACK), ("MP", "status", STATUS)]
        for kind, sub, ty in want:
            found = [t.split("/") for t in tokens if t.split("/")[5:6] == [kind] and t.split("/")[9:10] == [mangled + sub]]
            check(len(found) == 1, f"one {kind} token for {sub}: {tokens}")
            check(found[0][6:9] == ["%", "%", "parol6"] and found[0][10:12] == list(ty), f"token of {sub}: {found[0]}")
        report["action_tokens"] = len(want)

        with lock:
            start = list(got["js"][-1])
        moved = [start[0] + 0.2] + start[1:]
        n_before = len(got["js"])
        if not args.remote:
            ok, _ = send_goal(goal_request(uuid_of(1), [(start, 0.0), (moved, 1.0)]))
            check(not ok, "a goal is rejected without --allow-remote-control")
            status, code, why = get_result(uuid_of(1))
            check(status == ABORTED and code == -1 and "--allow-remote-control" in why, f"its result: {status} {code} {why}")
            time.sleep(0.5)
            with lock:
                during = got["js"][n_before:]
            check(all(max(abs(a - b) for a, b in zip(m, start)) < 1e-4 for m in during), "no motion")
            report["refusal"] = why
        else:
            if not args.tolerance:
                nan = list(moved)
                nan[2] = float("nan")
                far = list(start)
                far[1] = 3.0
                old = (int(time.time()) - 100, 0)
                hostile = [
                    ("malformed CDR", b"\x00\x01\x00\x00" + uuid_of(20) + b"\xff\xff", None),
                    ("wrong joint names", goal_request(uuid_of(21), [(moved, 1.0)], names=("a", "b", "c", "d", "e", "f")), -2),
                    ("NaN", goal_request(uuid_of(22), [(start, 0.0), (nan, 1.0)]), -1),
                    ("out of limits", goal_request(uuid_of(23), [(start, 0.0), (far, 5.0)]), -1),
                    ("times not increasing", goal_request(uuid_of(24), [(moved, 1.0), (start, 1.0)]), -1),
                    ("multi-DOF", goal_request(uuid_of(25), [(moved, 1.0)], multi_dof=True), -1),
                    ("old header stamp", goal_request(uuid_of(26), [(moved, 1.0)], stamp=old), -3),
                    ("tolerance of an unknown joint", goal_request(uuid_of(27), [(moved, 1.0)], tolerance=[("J9", 0.1)]), -2),
                ]
                refusals = {}
                for i, (name, payload, code) in enumerate(hostile):
                    ok, _ = send_goal(payload)
                    check(not ok, f"{name}: rejected")
                    status, got_code, why = get_result(uuid_of(20 + i))
                    if code is None:
                        check(status == 0, f"{name}: no goal known: {status}")
                    else:
                        check(status == ABORTED and got_code == code, f"{name}: result {status} {got_code} {why}")
                    refusals[name] = [got_code, why]
                with lock:
                    during = got["js"][n_before:]
                check(all(max(abs(a - b) for a, b in zip(m, start)) < 1e-4 for m in during), "no motion while refusing")
                report["refusals"] = refusals

            path_ok = [(n, PATH_TOLERANCE_OK_RAD) for n in NAMES]
            ok, stamp = send_goal(goal_request(uuid_of(2), [(start, 0.0), (moved, 1.0)], tolerance=[("J1", 0.05)],
                                               path_tolerance=path_ok))
            check(ok and abs(stamp[0] - time.time()) < 5, f"the valid goal is accepted: {stamp}")
            status, code, why = get_result(uuid_of(2))
            check(status == SUCCEEDED and code == 0, f"the valid goal succeeded: {status} {code} {why}")
            time.sleep(0.3)
            with lock:
                end = got["js"][-1]
                statuses = [dict(s).get(uuid_of(2)) for s in got["status"]]
            check(abs(end[0] - moved[0]) < 0.005, f"J1 ends at the goal: {end[0]} vs {moved[0]}")
            check(2 in statuses and statuses[-1] == SUCCEEDED, f"status EXECUTING then SUCCEEDED: {statuses}")
            report["end_error_rad"] = end[0] - moved[0]
            with lock:
                fb = [m for m in got["feedback"] if m.get("goal_id") == uuid_of(2)]
                bad = [m for m in got["feedback"] if "decode_error" in m]
                by_stamp = dict(got["js_by_stamp"])
            check(not bad, f"every feedback message decodes: {bad[:1]}")
            report["feedback_messages"] = len(fb)
            report["tracking_lag_rad"] = check_feedback(fb, by_stamp, moved)

            if not args.tolerance:
                ok, _ = send_goal(goal_request(uuid_of(3), [(moved, 0.0), (start, 3.0)]))
                check(ok, "the slow goal is accepted")
                time.sleep(0.8)
                w = Writer()
                w.b += uuid_of(3)
                w.i32(0)
                w.u32(0)
                r = call("cancel_goal", CANCEL_GOAL, w.payload())
                return_code = r.b[0]
                r.o = 1
                canceling = r.u32()
                check(return_code == 0 and canceling == 1, f"the cancel is taken: {return_code} {canceling}")
                status, code, why = get_result(uuid_of(3))
                check(status == CANCELED, f"the slow goal is cancelled: {status} {code} {why}")
                a, b = j1_half_a_second_apart()
                check(abs(a - b) < 1e-4 and abs(b - start[0]) > 0.02, f"the arm stopped short of the goal: {a} {b}")
                report["cancelled_at_rad"] = b - start[0]

            if args.tolerance:
                # a path tolerance the simulation's tracking lag exceeds: stopped, aborted with -4
                with lock:
                    here = list(got["js"][-1])
                there = [here[0] + 0.2] + here[1:]
                ok, _ = send_goal(goal_request(uuid_of(4), [(here, 0.0), (there, 1.0)],
                                               path_tolerance=[("J1", PATH_TOLERANCE_TIGHT_RAD)]))
                check(ok, "the goal with a tight path tolerance is accepted")
                status, code, why = get_result(uuid_of(4))
                check(status == ABORTED and code == -4 and "J1" in why and "path_tolerance" in why,
                      f"the tight goal aborts with PATH_TOLERANCE_VIOLATED naming J1: {status} {code} {why}")
                a, b = j1_half_a_second_apart()
                with lock:
                    statuses = [dict(s).get(uuid_of(4)) for s in got["status"]]
                    fb = [m for m in got["feedback"] if m.get("goal_id") == uuid_of(4)]
                check(abs(a - b) < 1e-4 and abs(b - there[0]) > 0.1, f"the arm stopped early: {a} {b} (goal {there[0]})")
                check(statuses[-1] == ABORTED, f"status ABORTED: {statuses}")
                check(fb, "feedback while the tight goal ran")
                report["path_abort"] = {"error_string": why, "moved_rad": b - here[0], "feedback_messages": len(fb)}
                if args.events:
                    # the goal and its violation, read back from /events by an independent Foxglove client
                    report["path_abort"]["events"] = events.wait_for(["network command from ros2 ", f"goal {uuid_of(4).hex()}", why], 5.0)

                # a goal tolerance the arm does not reach: GOAL_TOLERANCE_VIOLATED once goal_time_tolerance has passed
                with lock:
                    here = list(got["js"][-1])
                there = [here[0] - 0.1] + here[1:]
                sent_at = time.monotonic()
                ok, _ = send_goal(goal_request(uuid_of(5), [(here, 0.0), (there, 0.5)], tolerance=[("J1", 1e-9)],
                                               goal_time=GOAL_TIME_TOLERANCE_S))
                check(ok, "the goal with an unreachable goal tolerance is accepted")
                status, code, why = get_result(uuid_of(5))
                took = time.monotonic() - sent_at
                check(status == ABORTED and code == -5 and "J1" in why and "goal_tolerance" in why,
                      f"it aborts with GOAL_TOLERANCE_VIOLATED naming J1: {status} {code} {why}")
                check(took >= 0.5 + GOAL_TIME_TOLERANCE_S - 0.05, f"after its goal_time_tolerance: {took:.3f} s")
                report["goal_abort"] = {"error_string": why, "result_after_s": took}

                # a velocity path tolerance (position unchecked) the tracking exceeds: stopped, -4
                time.sleep(0.5)
                with lock:
                    here = list(got["js"][-1])
                there = [here[0] + 0.2] + here[1:]
                ok, _ = send_goal(goal_request(uuid_of(6), [(here, 0.0), (there, 1.0)],
                                               path_tolerance=[("J1", 0.0, PATH_VELOCITY_TOLERANCE_TIGHT_RAD_S)]))
                check(ok, "the goal with a tight velocity path tolerance is accepted")
                status, code, why = get_result(uuid_of(6))
                check(status == ABORTED and code == -4 and "J1" in why and "rad/s" in why and "velocity" in why,
                      f"it aborts with PATH_TOLERANCE_VIOLATED naming J1's velocity: {status} {code} {why}")
                a, b = j1_half_a_second_apart()
                check(abs(a - b) < 1e-4 and abs(b - there[0]) > 0.1, f"the arm stopped early: {a} {b} (goal {there[0]})")
                report["velocity_abort"] = {"error_string": why, "moved_rad": b - here[0]}
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
        check(proc.returncode == 130, f"exit 130 after SIGINT, got {proc.returncode}: {err}")
        summary = json.loads(out.strip().splitlines()[-1])
        report["summary"] = {k: summary[k] for k in ("network_commands", "network_commands_refused")}
        print(json.dumps({"ok": True, **report}))
        return 0
    except peer.Failure as e:
        print(json.dumps({"ok": False, "failure": str(e), **report}))
        return 1
    finally:
        events.stop()
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for s in subs:
            s.undeclare()
        session.close()


if __name__ == "__main__":
    sys.exit(main())
