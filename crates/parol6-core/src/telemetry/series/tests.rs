use super::*;
use crate::kinematics::TcpPose;
use crate::limits::LimitZone;
use crate::telemetry::ring::LiveRing;
use crate::telemetry::sample::JointTelemetry;

fn sample(t: f64, q0: f64, cmd0: f64) -> TelemetrySample {
    let joint = |q: f64, cmd: f64| JointTelemetry {
        cmd_q_rad: cmd,
        cmd_qd_rad_s: 0.0,
        cmd_qdd_rad_s2: 0.0,
        q_rad: q,
        qd_rad_s: 0.0,
        qdd_rad_s2: 0.0,
        drive: 2.0,
        zone: LimitZone::Safe,
    };
    TelemetrySample {
        seq: (t * 1000.0) as u64,
        time_s: t,
        joints: vec![joint(q0, cmd0), joint(0.5, 0.5)],
        drive: DriveKind::TorqueNm,
        tcp: TcpPose::from_xyz_rpy([0.1, 0.2, 0.3], [0.0, 0.1, 0.2]),
        worst_zone: None,
        program_step: None,
        link: None,
    }
}

/// A store of `n` samples at 250 Hz of a sine on joint 1.
fn sine_store(n: usize) -> SeriesStore {
    let mut st = SeriesStore::new(2, f64::INFINITY);
    for k in 0..n {
        let t = k as f64 / 250.0;
        st.push_sample(&sample(t, (t * 3.0).sin(), 0.0));
    }
    st
}

fn brute_min_max(st: &SeriesStore, col: usize, a: usize, b: usize) -> (f32, f32) {
    (a..b).map(|i| st.recent.columns[col].values[i]).fold(EMPTY, |m, v| merge(m, (v, v)))
}

#[test]
fn columns_are_named_in_order() {
    let st = SeriesStore::new(6, 600.0);
    assert_eq!(st.ids().len(), 5 * 6 + 6);
    assert_eq!(st.column(SeriesId { quantity: Quantity::TrackingError, index: 0 }), Some(24));
    assert_eq!(st.column(SeriesId { quantity: Quantity::TcpOrientation, index: 2 }), Some(35));
    assert_eq!(st.column(SeriesId { quantity: Quantity::Position, index: 6 }), None);
}

#[test]
fn pyramid_ranges_match_the_raw_samples() {
    let st = sine_store(5000);
    for (a, b) in [(0, 5000), (3, 4), (7, 9), (8, 16), (1, 4999), (123, 2345), (4096, 5000), (17, 18)] {
        assert_eq!(
            st.recent.range_min_max(&st.recent.columns[0], a as u64, b as u64),
            brute_min_max(&st, 0, a, b),
            "[{a}, {b})"
        );
    }
}

#[test]
fn decimation_gives_two_points_per_pixel_and_keeps_the_extremes() {
    let st = sine_store(150_000); // 10 minutes at 250 Hz
    let mut out = Vec::new();
    st.decimated(0, 0.0, 600.0, 800, &mut out);
    assert!(out.len() <= 2 * 800 + 2 && out.len() >= 2 * 800 - 2, "{} points", out.len());
    let lo = out.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let hi = out.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
    let (blo, bhi) = brute_min_max(&st, 0, 0, 150_000);
    assert_eq!((lo as f32, hi as f32), (blo, bhi));
    assert!(out.windows(2).all(|w| w[1][0] >= w[0][0]), "time never goes back");
    // a short window is drawn from the raw samples
    st.decimated(0, 10.0, 11.0, 800, &mut out);
    assert_eq!(out.len(), 250 + 2);
    // nothing outside the data, nothing for an empty window
    st.decimated(0, 700.0, 800.0, 800, &mut out);
    assert!(out.len() <= 1);
    st.decimated(0, 5.0, 5.0, 800, &mut out);
    assert!(out.is_empty());
}

#[test]
fn tracking_error_rms_and_max_over_a_window() {
    let mut st = SeriesStore::new(2, f64::INFINITY);
    // error +0.01 for 100 samples then −0.03 for 100 samples
    for k in 0..200 {
        let e = if k < 100 { 0.01 } else { -0.03 };
        st.push_sample(&sample(k as f64 * 0.01, 0.0, e));
    }
    let col = st.column(SeriesId { quantity: Quantity::TrackingError, index: 0 }).unwrap_or(usize::MAX);
    let s = st.window_stats(col, 0.0, 0.995).unwrap();
    assert_eq!(s.samples, 100);
    assert!((s.rms.unwrap() - 0.01).abs() < 1e-6 && (s.max_abs - 0.01).abs() < 1e-6, "{s:?}");
    let s = st.window_stats(col, 0.0, 10.0).unwrap();
    let expect = ((0.01f64.powi(2) + 0.03f64.powi(2)) / 2.0).sqrt();
    assert!((s.rms.unwrap() - expect).abs() < 1e-6, "{s:?}");
    assert!((s.max_abs - 0.03).abs() < 1e-6 && (s.min + 0.03).abs() < 1e-6);
    // position series have no RMS
    assert_eq!(st.window_stats(0, 0.0, 10.0).map(|s| s.rms), Some(None));
    assert!(st.window_stats(col, 50.0, 60.0).is_none());
}

#[test]
fn a_live_span_expires_old_samples_and_stays_exact() {
    let mut st = SeriesStore::new(2, 10.0);
    for k in 0..10_000 {
        let t = k as f64 * 0.004;
        st.push_sample(&sample(t, (t * 7.0).sin(), 0.02 * (t * 5.0).cos()));
    }
    let (t0, t1) = st.time_range_s().unwrap();
    assert!((t1 - t0 - 10.0).abs() < 0.005, "{t0} {t1}");
    assert_eq!(st.len(), 2501);
    let n = st.len();
    assert_eq!(
        st.recent.range_min_max(&st.recent.columns[0], st.recent.base, st.recent.end()),
        brute_min_max(&st, 0, 0, n)
    );
    let off = st.recent.base as usize;
    for (a, b) in [(5, 2000), (0, 1), (1000, 2501), (0, 2501)] {
        let got = st.recent.range_min_max(&st.recent.columns[0], (off + a) as u64, (off + b) as u64);
        assert_eq!(got, brute_min_max(&st, 0, a, b));
    }
    // the RMS after expiry equals a direct computation
    let col = st.column(SeriesId { quantity: Quantity::TrackingError, index: 0 }).unwrap_or(0);
    let direct = (st.recent.columns[col].values.iter().map(|&v| f64::from(v).powi(2)).sum::<f64>() / n as f64).sqrt();
    let rms = st.window_stats(col, t0, t1).and_then(|s| s.rms).unwrap();
    assert!((rms - direct).abs() < 1e-6, "{rms} vs {direct}");
}

#[test]
fn live_views_are_ingested_once_and_a_new_source_starts_again() {
    let mut ring = LiveRing::new(2, 600.0, 600.0, 250.0);
    for k in 0..1000 {
        ring.push(&sample(k as f64 * 0.004, 0.0, 0.0));
    }
    let mut st = SeriesStore::new(2, 600.0);
    assert_eq!(st.ingest_live(&ring.view()), 1000);
    assert_eq!(st.ingest_live(&ring.view()), 0);
    for k in 1000..1300 {
        ring.push(&sample(k as f64 * 0.004, 0.0, 0.0));
    }
    assert_eq!(st.ingest_live(&ring.view()), 300);
    assert_eq!(st.len(), 1300);
    let mut other = LiveRing::new(2, 600.0, 600.0, 250.0);
    other.push(&sample(0.5, 0.0, 0.0));
    assert_eq!(st.ingest_live(&other.view()), 1);
    assert_eq!(st.len(), 1);
}

/// Issue 32 minor: "Switching robot ↔ simulation clears the plot history." Another backend's
/// view, shifted onto the kept clock, continues the rows; its own older rows are left out.
#[test]
fn another_backends_view_shifted_continues_the_kept_rows() {
    let mut sim = LiveRing::new(2, 600.0, 600.0, 250.0);
    for k in 0..1000 {
        sim.push(&sample(k as f64 * 0.004, 0.0, 0.0));
    }
    let mut st = SeriesStore::new(2, 600.0);
    assert_eq!(st.ingest_live(&sim.view()), 1000);
    let last = st.time_range_s().unwrap().1;
    // the robot's clock starts at 0 (its connection) and has 2 s of rows by the switch
    let mut robot = LiveRing::new(2, 600.0, 600.0, 250.0);
    for k in 0..500 {
        robot.push(&sample(k as f64 * 0.004, 0.0, 0.0));
    }
    let shift = last - robot.view().latest_time_s().unwrap();
    assert_eq!(st.ingest_live_shifted(&robot.view(), shift), 0, "rows before the switch are left out");
    for k in 500..600 {
        robot.push(&sample(k as f64 * 0.004, 0.0, 0.0));
    }
    assert_eq!(st.ingest_live_shifted(&robot.view(), shift), 100);
    assert_eq!(st.len(), 1100, "the simulation's rows are kept");
    let (first, newest) = st.time_range_s().unwrap();
    assert_eq!(first, 0.0);
    assert!((newest - (last + 0.4)).abs() < 1e-9, "{newest}");
}

#[test]
fn rows_at_a_time_and_raw_windows() {
    let st = sine_store(1000);
    let q = st.joint_positions_at(1.0).unwrap();
    assert_eq!(q.len(), 2);
    assert!((q[0] - 3.0f64.sin()).abs() < 1e-6);
    assert!((st.joint_positions_at(-5.0).unwrap()[0]).abs() < 1e-9, "before the start: the first sample");
    assert_eq!(st.raw_window(1.0, 2.0).count(), 251);
    assert!(SeriesStore::new(2, 1.0).row_at(0.0).is_none());
}

proptest::proptest! {
    /// The RMS of any window, after any expiry and with NaNs among the values, equals a direct
    /// computation over the kept raw values (sums of squares are kept only every 64 samples).
    #[test]
    fn window_rms_matches_the_raw_values(
        values in proptest::collection::vec(proptest::option::weighted(0.95, -1.0f32..1.0), 1..700),
        span_s in 0.2f64..4.0,
        a_frac in 0.0f64..1.0,
        len_frac in 0.0f64..1.0,
    ) {
        let mut st = SeriesStore::new(1, span_s);
        let col = st.column(SeriesId { quantity: Quantity::TrackingError, index: 0 }).unwrap_or(0);
        let mut row = vec![f32::NAN; st.ids().len()];
        for (k, v) in values.iter().enumerate() {
            row[col] = v.unwrap_or(f32::NAN);
            st.push_row(k as f64 * 0.004, &row);
        }
        let kept: Vec<(f64, f32)> =
            st.recent.times_s.iter().copied().zip(st.recent.columns[col].values.iter().copied()).collect();
        let a = ((kept.len() - 1) as f64 * a_frac) as usize;
        let b = (a + ((kept.len() - a) as f64 * len_frac) as usize).clamp(a + 1, kept.len());
        let (t0, t1) = (kept[a].0, kept[b - 1].0);
        let direct = kept[a..b].iter().map(|&(_, v)| if v.is_finite() { f64::from(v).powi(2) } else { 0.0 }).sum::<f64>();
        let direct = (direct / (b - a) as f64).sqrt();
        let finite = kept[a..b].iter().any(|(_, v)| v.is_finite());
        match st.window_stats(col, t0, t1) {
            Some(s) => {
                let rms = s.rms.unwrap_or(f64::NAN);
                proptest::prop_assert!((rms - direct).abs() < 1e-9, "{} vs {}", rms, direct);
                proptest::prop_assert_eq!(s.samples, b - a);
            }
            None => proptest::prop_assert!(!finite),
        }
    }
}

/// A live store keeps the newest minute of a 1 kHz source whole and older samples as 4 ms
/// min/max pairs: half the rows, and a one-sample spike still in the plotted min / max.
#[test]
fn a_live_store_summarises_after_a_minute_and_keeps_every_peak() {
    let mut st = SeriesStore::live(2, 600.0, 60.0);
    for k in 0..120_000u64 {
        let t = k as f64 * 1e-3;
        let q = if k == 10_002 { 5.0 } else { (t * 3.0).sin() };
        st.push_sample(&sample(t, q, 0.01));
    }
    assert!((89_900..=90_100).contains(&st.len()), "{} rows", st.len());
    let summary_until = st.summary_before_s().unwrap_or(0.0);
    assert!((summary_until - 60.0).abs() < 0.01, "{summary_until}");
    let mut out = Vec::new();
    st.decimated(0, 0.0, 120.0, 800, &mut out);
    let top = out.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(top, 5.0, "the spike at 10.002 s is plotted");
    assert!(out.windows(2).all(|w| w[1][0] >= w[0][0]), "time never goes back");
    assert_eq!(st.window_stats(0, 9.0, 11.0).map(|s| s.max), Some(5.0));
    let col = st.column(SeriesId { quantity: Quantity::TrackingError, index: 0 }).unwrap_or(0);
    let rms = st.window_stats(col, 0.0, 120.0).and_then(|s| s.rms).unwrap_or(f64::NAN);
    assert!(rms.is_finite() && rms > 0.0, "{rms}");
    assert_eq!(st.time_range_s(), Some((0.0, 119_999.0 * 1e-3)));
    assert_eq!(st.raw_window(0.0, 120.0).count(), st.len());
}

/// A live store fed from the live ring, view by view or all at once from a view that already
/// holds a summary, holds the rows of a store fed sample by sample.
#[test]
fn a_live_store_fed_from_the_ring_equals_one_fed_sample_by_sample() {
    let mut ring = LiveRing::new(2, 600.0, 60.0, 1000.0);
    let mut by_view = SeriesStore::live(2, 600.0, 60.0);
    let mut direct = SeriesStore::live(2, 600.0, 60.0);
    for k in 0..90_000u64 {
        let t = k as f64 * 1e-3;
        let s = sample(t, (t * 5.0).sin(), 0.02 * (t * 2.0).cos());
        ring.push(&s);
        direct.push_sample(&s);
        if k % 50 == 49 {
            by_view.ingest_live(&ring.view());
        }
    }
    by_view.ingest_live(&ring.view());
    let mut fresh = SeriesStore::live(2, 600.0, 60.0);
    fresh.ingest_live(&ring.view());
    let rows = |st: &SeriesStore| {
        st.raw_window(f64::NEG_INFINITY, f64::INFINITY)
            .map(|(t, r)| (t.to_bits(), r.iter().map(|v| v.to_bits()).collect::<Vec<_>>()))
            .collect::<Vec<_>>()
    };
    let want = rows(&direct);
    assert_eq!(rows(&by_view), want);
    // a fresh store takes the ring's summary as it is: the same rows, apart from where the
    // ring's full-rate blocks end (whole blocks are summarised)
    let got = rows(&fresh);
    let from = want.len().saturating_sub(59_000);
    assert_eq!(got[got.len() - 59_000..], want[from..]);
    assert_eq!(got[..1000], want[..1000]);
}

/// Bytes per stored second of the live ring: 152 per sample of six joints (a 100 Hz robot:
/// 15.2 kB/s; 68 kB/s when it kept whole samples).
#[test]
fn the_live_ring_keeps_what_the_plots_draw_in_f32_rows() {
    let mut ring = LiveRing::new(6, 600.0, 60.0, 1000.0);
    let mut s = sample(0.0, 0.0, 0.0);
    s.joints = vec![s.joints[0]; 6];
    for k in 0..60_000u64 {
        s.time_s = k as f64 * 0.01;
        ring.push(&s);
    }
    let per_s = ring.heap_bytes() as f64 / 600.0;
    assert!(per_s <= 15_500.0, "{per_s} bytes per stored second");
}
