//! Drives the session's last-line guard and measurement plausibility filter (pure functions)
//! with arbitrary targets, references, periods and measured streams: nothing may panic, every
//! guarded MOVE target lies within the step limits (a target outside them is refused) and
//! within the speed limit × elapsed periods (+1) of the reference, and an accepted measurement
//! never jumps further than the filter's own bound.
//! Run with `cargo +nightly fuzz run session_guard` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;
use parol6_hw::frame::{CommandCode, CommandFrame};
use parol6_hw::session::guard::{
    Plausibility, PlausibilityFilter, allowed_target_range, guard_frame, max_plausible_jump, max_target_step,
};
use parol6_hw::units::limits_steps;

fn i32_at(data: &[u8], k: usize) -> i32 {
    let mut b = [0u8; 4];
    for (i, x) in b.iter_mut().enumerate() {
        *x = data.get(k * 4 + i).copied().unwrap_or(0);
    }
    i32::from_le_bytes(b)
}

fuzz_target!(|data: &[u8]| {
    let lim = limits_steps();
    let period_s = 0.002 + f64::from(data.first().copied().unwrap_or(0)) * 1e-4;
    // Guard: chunks of 6 targets after a reference inside the limits.
    let mut reference: [i32; 6] = std::array::from_fn(|i| i32_at(data, i).clamp(lim[i].0, lim[i].1));
    let mut k = 6;
    while k * 4 + 24 <= data.len() {
        let periods = u32::from(data[k * 4] % 4) + 1;
        let mut f = CommandFrame::new(CommandCode::Move);
        f.fields.positions_steps = std::array::from_fn(|i| i32_at(data, k + i));
        if guard_frame(&mut f, Some((&reference, periods)), period_s).is_ok() {
            for i in 0..6 {
                let t = f.fields.positions_steps[i];
                let (lo, hi) = allowed_target_range(i, reference[i], period_s, periods);
                assert!((lo..=hi).contains(&t));
                assert!((lim[i].0..=lim[i].1).contains(&t));
                assert!((t - reference[i]).abs() <= max_target_step(i, period_s, periods));
            }
            reference = f.fields.positions_steps;
        }
        let mut idle = CommandFrame::new(CommandCode::Idle);
        idle.fields.positions_steps = f.fields.positions_steps;
        let _ = guard_frame(&mut idle, None, period_s);
        k += 6;
    }
    // Plausibility: the same bytes as a measured stream with arbitrary timing.
    let mut filter = PlausibilityFilter::default();
    let mut t = 0.0;
    let mut last: Option<[i32; 6]> = None;
    for (n, chunk) in data.chunks(25).enumerate() {
        t += f64::from(chunk[0]) * 1e-3;
        let m: [i32; 6] = std::array::from_fn(|i| i32_at(&chunk[1..], i) >> 8);
        if filter.check(&m, t, period_s) == Plausibility::Accepted {
            if let Some(p) = last {
                for i in 0..6 {
                    assert!((m[i] - p[i]).abs() <= max_plausible_jump(i, 60.0), "frame {n}");
                }
            }
            last = Some(m);
        }
    }
});
