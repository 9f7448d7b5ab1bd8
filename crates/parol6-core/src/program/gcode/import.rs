//! G-code → [`Program`]: the modal state (units, distance mode, plane, feed, work offset,
//! blend, position) tracked line by line. See the [module docs](super) for the dialect.

use super::arc::{self, Plane};
use super::block::{AXES, Block, Group};
use super::header::Header;
use super::lexer::{Word, words_of_line};
use super::{
    ARC_RADIUS_TOLERANCE_MM, AbcConvention, GcodeError, GcodeGripper, GcodeImportOptions, MAX_ANGLE_DEG,
    MAX_GCODE_BYTES, MAX_STEPS, format_number,
};
use crate::program::compile::{MAX_POSITION_MM, MAX_WAIT_S, MIN_TCP_SPEED_MM_S};
use crate::program::{GripperAction, PoseMm, Program, SourcedStep, Step};

const MM_PER_INCH: f64 = 25.4;
/// Start and end closer than this are one point (a full circle), mm.
const SAME_POINT_MM: f64 = 1e-6;
/// The normal axis may change this much on an arc before it is a helix, mm.
const HELIX_TOLERANCE_MM: f64 = 1e-3;

/// Reads G-code `text` into a program (see the module docs for the dialect).
pub fn parse_gcode(text: &str, options: &GcodeImportOptions) -> Result<Program, GcodeError> {
    if text.len() > MAX_GCODE_BYTES {
        return Err(GcodeError::at_line(
            0,
            format!(
                "the file is {} bytes; G-code files are limited to {} MiB",
                text.len(),
                MAX_GCODE_BYTES / (1024 * 1024)
            ),
        ));
    }
    let mut state = State::new(options);
    let mut header = Header::new(options.abc);
    for (i, raw) in text.split('\n').enumerate() {
        let line = i + 1;
        let words = words_of_line(line, raw)?;
        if let Some(abc) = header.line(line, raw, !words.is_empty())? {
            state.abc = abc;
        }
        if !words.is_empty() {
            state.run_line(line, words)?;
        }
        if state.steps.len() > MAX_STEPS {
            return Err(GcodeError::at_line(line, format!("the program has more than {MAX_STEPS} steps")));
        }
    }
    Ok(Program { name: options.name.clone(), steps: state.steps, ..Program::default() })
}

struct State {
    steps: Vec<SourcedStep>,
    /// How A, B, C make a rotation.
    abc: AbcConvention,
    /// Base-frame position: X, Y, Z (mm), A, B, C (deg, in `abc`).
    pos: [f64; 6],
    home: PoseMm,
    mm_per_unit: f64,
    absolute: bool,
    plane: Plane,
    motion: Option<u32>,
    feed_mm_s: Option<f64>,
    work: usize,
    offsets: [[f64; 6]; 6],
    blend_mm: Option<f64>,
    gripper: GcodeGripper,
    /// Line of the program end (M2/M30).
    ended: Option<(usize, String)>,
}

impl State {
    fn new(o: &GcodeImportOptions) -> Self {
        let [x, y, z] = o.start_pose.position_mm;
        Self {
            steps: Vec::new(),
            abc: o.abc.convention,
            // X Y Z where the program starts; A B C 0 until given, as in the official parser
            pos: [x, y, z, 0.0, 0.0, 0.0],
            home: o.home_pose,
            mm_per_unit: 1.0,
            absolute: true,
            plane: Plane::Xy,
            motion: None,
            feed_mm_s: None,
            work: 0,
            offsets: o.work_offsets,
            blend_mm: None,
            gripper: o.gripper,
            ended: None,
        }
    }

    /// `X Y Z A B C` of a pose.
    fn axes_of(&self, p: &PoseMm) -> [f64; 6] {
        let abc = self.abc.from_rpy_deg(p.rpy_deg);
        [p.position_mm[0], p.position_mm[1], p.position_mm[2], abc[0], abc[1], abc[2]]
    }

    /// The pose of `X Y Z A B C`.
    fn pose_of(&self, a: &[f64; 6]) -> PoseMm {
        PoseMm { position_mm: [a[0], a[1], a[2]], rpy_deg: self.abc.to_rpy_deg([a[3], a[4], a[5]]) }
    }

    fn push(&mut self, line: usize, step: Step) {
        self.steps.push(SourcedStep { step, line });
    }

    fn run_line(&mut self, line: usize, words: Vec<Word>) -> Result<(), GcodeError> {
        if let (Some((end, code)), Some(first)) = (&self.ended, words.first()) {
            return Err(GcodeError::at_word(
                line,
                &first.text,
                format!("after the program end ({code} on line {end})"),
            ));
        }
        let mut b = Block::sort(line, words)?;
        if let Some((code, _)) = b.code(Group::Units) {
            self.mm_per_unit = if code == 20 { MM_PER_INCH } else { 1.0 };
        }
        if let Some((code, _)) = b.code(Group::Plane) {
            self.plane = [Plane::Xy, Plane::Zx, Plane::Yz][(code - 17) as usize];
        }
        if let Some((code, _)) = b.code(Group::Distance) {
            self.absolute = code == 90;
        }
        if let Some((code, _)) = b.code(Group::Work) {
            self.work = (code - 54) as usize;
        }
        if let Some((code, w)) = b.code(Group::Path) {
            self.blend_mm = if code == 61 { None } else { Some(self.blend_radius(&mut b, &w)?) };
        }
        if let Some(f) = b.take('F') {
            self.feed_mm_s = Some(self.feed(line, &f)?);
        }
        let motion = b.code(Group::Motion);
        if let Some((10, w)) = &motion {
            self.set_offset(&mut b, w)?;
        }
        if let Some((code @ 3..=5, w)) = b.m.clone() {
            self.gripper_step(&mut b, code, &w)?;
        }
        match motion {
            Some((4, w)) => self.dwell(&mut b, &w)?,
            Some((28, w)) => {
                if let Some(a) = AXES.iter().find_map(|&a| b.take(a)) {
                    return Err(GcodeError::at_word(
                        line,
                        &a.text,
                        format!("{} with axis words (an intermediate point) is not supported", w.text),
                    ));
                }
                self.push(line, Step::Home { speed_fraction: None });
                self.pos = self.axes_of(&self.home);
            }
            Some((10, _)) => {}
            Some((code, w)) => {
                self.motion = Some(code);
                self.move_to(&mut b, code, Some(&w))?;
            }
            None => {
                let moving = "XYZABCIJKR".chars().any(|c| b.has(c));
                match self.motion {
                    Some(code) if moving => self.move_to(&mut b, code, None)?,
                    None if moving => {
                        let first = b.params.iter().find(|(w, _)| "XYZABCIJKR".contains(w.letter));
                        let text = first.map(|(w, _)| w.text.clone()).unwrap_or_default();
                        return Err(GcodeError::at_word(
                            line,
                            &text,
                            "no motion code yet: start the move with G0, G1, G2 or G3",
                        ));
                    }
                    _ => {}
                }
            }
        }
        if let Some((code @ (0 | 1 | 2 | 30), w)) = b.m.clone() {
            match code {
                0 | 1 => self.push(line, Step::Pause { optional: code == 1 }),
                _ => self.ended = Some((line, w.text.clone())),
            }
        }
        b.leftover()
    }

    fn blend_radius(&self, b: &mut Block, code: &Word) -> Result<f64, GcodeError> {
        let Some(p) = b.take('P') else {
            return Err(GcodeError::at_word(b.line, &code.text, "G64 needs P: the corner radius"));
        };
        let r = p.value * self.mm_per_unit;
        if !(r > 0.0 && r <= MAX_POSITION_MM) {
            return Err(GcodeError::at_word(b.line, &p.text, "the corner radius must be above 0"));
        }
        Ok(r)
    }

    /// The feed of `F`, mm/s: any finite value from the PAROL6's slowest TCP speed up (a feed
    /// above its fastest is passed on: compiling slows that move down, with a warning).
    fn feed(&self, line: usize, f: &Word) -> Result<f64, GcodeError> {
        let mm_min = f.value * self.mm_per_unit;
        let mm_s = mm_min / 60.0;
        if !(mm_s.is_finite() && mm_s >= MIN_TCP_SPEED_MM_S) {
            return Err(GcodeError::at_word(
                line,
                &f.text,
                format!(
                    "feed {} mm/min is below the PAROL6's slowest {} mm/min ({MIN_TCP_SPEED_MM_S} mm/s)",
                    format_number(mm_min),
                    MIN_TCP_SPEED_MM_S * 60.0,
                ),
            ));
        }
        Ok(mm_s)
    }

    fn set_offset(&mut self, b: &mut Block, code: &Word) -> Result<(), GcodeError> {
        let line = b.line;
        match b.take('L') {
            Some(l) if l.value == 2.0 => {}
            Some(l) => return Err(GcodeError::at_word(line, &l.text, "only G10 L2 (set a work offset) is supported")),
            None => return Err(GcodeError::at_word(line, &code.text, "G10 needs L2 and P1…P6 (the work offset)")),
        }
        let p = match b.take('P') {
            Some(p) if (1.0..=6.0).contains(&p.value) && p.value.fract() == 0.0 => p,
            Some(p) => return Err(GcodeError::at_word(line, &p.text, "the work offset is P1 (G54) … P6 (G59)")),
            None => return Err(GcodeError::at_word(line, &code.text, "G10 L2 needs P1…P6 (the work offset)")),
        };
        for (k, w) in b.take_axes().into_iter().enumerate() {
            if let Some(w) = w {
                let v = if k < 3 { w.value * self.mm_per_unit } else { w.value };
                let (limit, unit) = if k < 3 { (MAX_POSITION_MM, "mm") } else { (MAX_ANGLE_DEG, "°") };
                if v.abs() > limit {
                    return Err(GcodeError::at_word(
                        line,
                        &w.text,
                        format!("an offset must lie within ±{limit} {unit}"),
                    ));
                }
                self.offsets[p.value as usize - 1][k] = v;
            }
        }
        Ok(())
    }

    fn gripper_step(&mut self, b: &mut Block, code: u32, w: &Word) -> Result<(), GcodeError> {
        let close = code != 5;
        let step = match self.gripper {
            GcodeGripper::Pneumatic => {
                let output = match b.take('P') {
                    None => 1,
                    Some(p) if p.value == 1.0 || p.value == 2.0 => p.value as u8,
                    Some(p) => return Err(GcodeError::at_word(b.line, &p.text, "the gripper port is P1 or P2")),
                };
                // the pneumatic gripper opens with its output high
                Step::SetOutput { output, on: !close }
            }
            GcodeGripper::Electric => {
                if let Some(p) = b.take('P') {
                    return Err(GcodeError::at_word(
                        b.line,
                        &p.text,
                        format!(
                            "{}: a port P is for the pneumatic gripper; this import drives the electric one",
                            w.text
                        ),
                    ));
                }
                let action = if close { GripperAction::Close } else { GripperAction::Open };
                Step::Gripper { action, position: None, speed: None, current_ma: None }
            }
        };
        self.push(b.line, step);
        Ok(())
    }

    fn dwell(&mut self, b: &mut Block, code: &Word) -> Result<(), GcodeError> {
        let line = b.line;
        let (p, s) = (b.take('P'), b.take('S'));
        let (seconds, w) = match (p, s) {
            (Some(p), None) => (p.value / 1000.0, p),
            (None, Some(s)) => (s.value, s),
            (Some(_), Some(s)) => return Err(GcodeError::at_word(line, &s.text, "G4 takes P (ms) or S (s), not both")),
            (None, None) => return Err(GcodeError::at_word(line, &code.text, "G4 needs P (ms) or S (s)")),
        };
        if !(0.0..=MAX_WAIT_S).contains(&seconds) {
            return Err(GcodeError::at_word(line, &w.text, format!("a dwell must lie in 0–{MAX_WAIT_S} s")));
        }
        if let Some(a) = AXES.iter().find_map(|&a| b.take(a)) {
            return Err(GcodeError::at_word(line, &a.text, "G4 takes no axis words"));
        }
        self.push(line, Step::Dwell { seconds });
        Ok(())
    }

    /// The target of the axis words (base frame), checked.
    fn target(&self, line: usize, axes: &[Option<Word>; 6]) -> Result<[f64; 6], GcodeError> {
        let mut t = self.pos;
        for (k, w) in axes.iter().enumerate() {
            let Some(w) = w else { continue };
            let v = if k < 3 { w.value * self.mm_per_unit } else { w.value };
            t[k] = if self.absolute { v + self.offsets[self.work][k] } else { self.pos[k] + v };
            let (limit, unit) = if k < 3 { (MAX_POSITION_MM, "mm") } else { (MAX_ANGLE_DEG, "°") };
            if !(t[k].is_finite() && t[k].abs() <= limit) {
                return Err(GcodeError::at_word(
                    line,
                    &w.text,
                    format!("{} would be {} {unit}, beyond ±{limit} {unit}", AXES[k], format_number(t[k])),
                ));
            }
        }
        Ok(t)
    }

    fn move_to(&mut self, b: &mut Block, code: u32, code_word: Option<&Word>) -> Result<(), GcodeError> {
        let line = b.line;
        let axes = b.take_axes();
        let has_axes = axes.iter().any(Option::is_some);
        let target = self.target(line, &axes)?;
        match code {
            0 | 1 if !has_axes => Ok(()),
            0 => {
                let pose = self.pose_of(&target);
                self.push(line, Step::MovePose { pose, config: None, speed_fraction: None, duration_s: None });
                self.pos = target;
                Ok(())
            }
            1 => {
                let step = Step::MoveL {
                    pose: self.pose_of(&target),
                    speed_mm_s: self.feed_mm_s,
                    blend_mm: self.blend_mm,
                    duration_s: None,
                };
                self.push(line, step);
                self.pos = target;
                Ok(())
            }
            _ => {
                let arc_word = "IJKR".chars().any(|c| b.has(c));
                if !has_axes && !arc_word {
                    // "G2" alone: only the mode
                    return Ok(());
                }
                let at = code_word.or_else(|| axes.iter().flatten().next()).map(|w| w.text.clone()).unwrap_or_default();
                self.arc(b, code == 3, &axes, target, &at)
            }
        }
    }

    fn arc(
        &mut self,
        b: &mut Block,
        ccw: bool,
        axes: &[Option<Word>; 6],
        target: [f64; 6],
        at: &str,
    ) -> Result<(), GcodeError> {
        let line = b.line;
        let plane = self.plane;
        let (ia, ib, n) = plane.axes();
        if let Some(w) = &axes[n]
            && (target[n] - self.pos[n]).abs() > HELIX_TOLERANCE_MM
        {
            return Err(GcodeError::at_word(
                line,
                &w.text,
                format!(
                    "helical arcs are not supported: {} changes on an arc in the {} plane ({})",
                    AXES[n],
                    plane.name(),
                    plane.code()
                ),
            ));
        }
        let offsets = ['I', 'J', 'K'].map(|c| b.take(c));
        if let Some(w) = &offsets[n] {
            let letters: String = [ia.min(ib), ia.max(ib)].iter().map(|&k| ['I', 'J', 'K'][k]).collect();
            return Err(GcodeError::at_word(
                line,
                &w.text,
                format!(
                    "{} is not a centre offset in the {} plane ({}): use {}",
                    w.letter,
                    plane.name(),
                    plane.code(),
                    letters.chars().map(String::from).collect::<Vec<_>>().join(" and ")
                ),
            ));
        }
        let radius = b.take('R');
        let (s, e) = (arc::in_plane(&self.pos, plane), arc::in_plane(&target, plane));
        let chord = (e[0] - s[0]).hypot(e[1] - s[1]);
        let full = chord < SAME_POINT_MM;
        let centre = match (&radius, offsets[ia].is_some() || offsets[ib].is_some()) {
            (Some(r), true) => return Err(GcodeError::at_word(line, &r.text, "an arc takes I/J/K or R, not both")),
            (None, false) => {
                return Err(GcodeError::at_word(line, at, "an arc needs I/J/K (its centre) or R (its radius)"));
            }
            (Some(r), false) => {
                let rm = r.value * self.mm_per_unit;
                if full {
                    return Err(GcodeError::at_word(
                        line,
                        &r.text,
                        "an R arc cannot end where it starts: give a full circle's centre with I/J/K",
                    ));
                }
                if rm.abs() < SAME_POINT_MM {
                    return Err(GcodeError::at_word(line, &r.text, "the radius must not be 0"));
                }
                arc::centre_from_radius(s, e, rm, ccw, ARC_RADIUS_TOLERANCE_MM).ok_or_else(|| {
                    GcodeError::at_word(
                        line,
                        &r.text,
                        format!(
                            "radius {} mm is less than half the distance to the end point ({} mm)",
                            format_number(rm.abs()),
                            format_number(0.5 * chord)
                        ),
                    )
                })?
            }
            (None, true) => {
                let off = |k: usize| offsets[k].as_ref().map_or(0.0, |w| w.value * self.mm_per_unit);
                let c = [s[0] + off(ia), s[1] + off(ib)];
                let r0 = (s[0] - c[0]).hypot(s[1] - c[1]);
                let r1 = (e[0] - c[0]).hypot(e[1] - c[1]);
                if r0 < SAME_POINT_MM {
                    return Err(GcodeError::at_word(
                        line,
                        at,
                        "the arc's radius is 0: I/J/K put the centre at the start",
                    ));
                }
                if (r0 - r1).abs() > ARC_RADIUS_TOLERANCE_MM {
                    return Err(GcodeError::at_word(
                        line,
                        at,
                        format!(
                            "the end point is {} mm from the centre, the start {} mm: not one circle (tolerance {ARC_RADIUS_TOLERANCE_MM} mm)",
                            format_number(r1),
                            format_number(r0)
                        ),
                    ));
                }
                c
            }
        };
        let sweep = arc::sweep(s, e, centre, ccw, full);
        let mut centre_3d = [0.0; 3];
        (centre_3d[ia], centre_3d[ib], centre_3d[n]) = (centre[0], centre[1], self.pos[n]);
        let radius = (s[0] - centre[0]).hypot(s[1] - centre[1]);
        if [centre[0], centre[1]].iter().any(|v| !(v.is_finite() && v.abs() + radius <= MAX_POSITION_MM)) {
            return Err(GcodeError::at_word(
                line,
                at,
                format!("the arc's circle reaches beyond ±{MAX_POSITION_MM} mm"),
            ));
        }
        let step = if full {
            if (3..6).any(|k| (target[k] - self.pos[k]).abs() > 1e-9) {
                return Err(GcodeError::at_word(line, at, "a full circle cannot change the orientation (A, B, C)"));
            }
            Step::MoveCircle {
                center_mm: centre_3d,
                normal: plane.normal(),
                angle_deg: sweep.to_degrees(),
                speed_mm_s: self.feed_mm_s,
            }
        } else {
            let mid = arc::rotate(s, centre, 0.5 * sweep);
            let mut via = [0.0; 3];
            (via[ia], via[ib], via[n]) = (mid[0], mid[1], 0.5 * (self.pos[n] + target[n]));
            Step::MoveC { via_mm: via, pose: self.pose_of(&target), speed_mm_s: self.feed_mm_s }
        };
        self.push(line, step);
        self.pos = target;
        Ok(())
    }
}
