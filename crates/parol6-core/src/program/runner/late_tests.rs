//! Steps handed over late: the schedule slips, the run never fails for it, and I/O and dwells
//! keep their place after the motions before them.

use super::tests::{sim, square};
use super::*;
use crate::motion::{BackendError, IoCommand};
use crate::program::{PoseMm, Step};
use crate::sim::SimHandle;
use std::sync::Mutex;
use std::sync::atomic::AtomicUsize;
use std::time::Instant;

/// A simulation whose scheduled steps number `late` (1-based) reach it only once its motion
/// clock is `by_s` past their time (on the schedule as it has slipped so far): the runner's
/// thread lost the processor, deterministically.
/// Records the TCP position commanded whenever an I/O command arrives.
struct LateBackend {
    inner: Arc<SimHandle>,
    model: RobotModel,
    late: Vec<usize>,
    by_s: f64,
    submitted: AtomicUsize,
    io_at_mm: Mutex<Vec<[f64; 3]>>,
}

impl RobotBackend for LateBackend {
    fn submit(&self, cmd: MotionCommand, at_s: Option<f64>) -> Result<(), BackendError> {
        if let Some(at) = at_s {
            let n = self.submitted.fetch_add(1, Ordering::SeqCst) + 1;
            if self.late.contains(&n) {
                let t0 = Instant::now();
                while self.inner.state().time_s < at + self.inner.state().schedule.delay_s + self.by_s {
                    assert!(t0.elapsed() < Duration::from_secs(10), "the clock does not run");
                    std::thread::sleep(Duration::from_millis(1));
                }
            }
        }
        self.inner.submit(cmd, at_s)
    }

    fn state(&self) -> Arc<RobotState> {
        self.inner.state()
    }

    fn io(&self, cmd: IoCommand) -> Result<(), BackendError> {
        let q = self.inner.state().commanded.q.clone();
        let p = self.model.tcp_isometry(&q).translation.vector * 1e3;
        self.io_at_mm.lock().expect("lock").push([p.x, p.y, p.z]);
        self.inner.io(cmd)
    }
}

/// Regression (issue 28): a step that reached the backend after its time started late, and the
/// next one, scheduled for when it should have ended, was refused: "the trajectory starts …
/// away from the commanded position (… that one started late, the schedule was not kept)".
/// Now the schedule slips; the output after the late line is set only once the line has ended.
#[test]
fn a_step_handed_over_late_slips_the_schedule_instead_of_failing_the_run() {
    let (model, sim) = sim(1.0);
    let (q, steps) = square(&model);
    let start_mm = model.tcp_isometry(&q).translation.vector * 1e3;
    let late = Arc::new(LateBackend {
        inner: sim.clone(),
        model: model.clone(),
        // the first line (the step before the output) and the last line
        late: vec![2, 4],
        by_s: 0.3,
        submitted: AtomicUsize::new(0),
        io_at_mm: Mutex::new(Vec::new()),
    });
    let program = Program::from_steps("square", steps);
    let done =
        ProgramRunner::start(late.clone(), model.clone(), program, RunOptions::default()).expect("thread").join();
    assert_eq!(done.state, RunState::Done, "{done:?}");
    assert_eq!(done.steps_done, 6);
    // both late steps slipped the schedule by at least 0.3 s each
    assert!(done.schedule_slip_s >= 0.6 - 1e-9, "slip {:.3} s", done.schedule_slip_s);
    let took = done.clock_s.1 - done.clock_s.0;
    assert!(took >= done.planned_s + 0.6 - 1e-6, "took {took:.3} s for {:.3} s planned", done.planned_s);
    // the output was set once the first line (40 mm along x) had ended, not on it: on the
    // second line (along y), which this thread, held up by the third line, reached late
    let io = late.io_at_mm.lock().expect("lock").clone();
    assert_eq!(io.len(), 1);
    assert!((io[0][0] - start_mm.x - 40.0).abs() < 0.01, "output set at {:?}, start {start_mm:?}", io[0]);
    // and the square closed where it started
    let end = model.tcp_isometry(&sim.state().commanded.q).translation.vector * 1e3;
    assert!((end - start_mm).norm() < 1e-3, "{end:?} vs {start_mm:?}");
}

/// A zig-zag of `n` unblended lines of `step_mm` in front of the arm (tool as at the start).
fn zigzag(model: &RobotModel, n: usize, step_mm: f64, blend_mm: Option<f64>) -> (Vec<f64>, Vec<Step>) {
    let (q, mut steps) = square(model);
    steps.truncate(1);
    let p0 = PoseMm::from_isometry(&model.tcp_isometry(&q));
    for k in 0..n {
        let mut p = p0;
        p.position_mm[0] += if k % 2 == 0 { step_mm } else { 0.0 };
        p.position_mm[1] += step_mm * ((k / 2) % 10) as f64 * 0.5;
        steps.push(Step::MoveL { pose: p, speed_mm_s: Some(100.0), blend_mm, duration_s: None });
    }
    (q, steps)
}

/// Regression (issue 28): 60 short unblended lines on a simulation 20 times faster than the
/// wall clock (the headless `program run`) failed at step 46: the runner retired one finished
/// step per 20 ms poll (0.4 s of motion clock), so the steps scheduled ahead ran out.
#[test]
fn many_short_lines_run_on_a_simulation_faster_than_the_wall_clock() {
    let (model, sim) = sim(20.0);
    for blend_mm in [None, Some(1.0)] {
        let (_, steps) = zigzag(&model, 60, 3.0, blend_mm);
        let n = steps.len();
        let program = Program::from_steps("zigzag", steps);
        let done =
            ProgramRunner::start(sim.clone(), model.clone(), program, RunOptions::default()).expect("thread").join();
        assert_eq!(done.state, RunState::Done, "blend {blend_mm:?}: {done:?}");
        assert_eq!(done.steps_done, n);
        std::thread::sleep(Duration::from_millis(50));
    }
}
