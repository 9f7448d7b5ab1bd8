//! Time functions: the TCP position (and optionally its orientation) written as expressions of
//! time, piece by piece, as in the LabVIEW GUI (its right-angled triangle test is three pieces).
//!
//! A `time_function` step holds the expressions themselves, so they stay editable and save in
//! the native JSON file:
//!
//! ```json
//! { "type": "time_function", "sample_rate_hz": 100, "pieces": [
//!     { "duration_s": 2, "x_mm": "20 + 25*t", "y_mm": "260", "z_mm": "250" },
//!     { "duration_s": 2, "x_mm": "70", "y_mm": "260 + 25*t", "z_mm": "250",
//!       "roll_deg": "180", "pitch_deg": "0", "yaw_deg": "90 + 5*sin(pi*t)" } ] }
//! ```
//!
//! - `t` is the **local** time of the piece in seconds: 0 where the piece starts, its
//!   `duration_s` where it ends. Each piece must start where the one before ends (within
//!   [`JOIN_TOLERANCE_MM`] and [`JOIN_TOLERANCE_DEG`]).
//! - `x_mm`, `y_mm`, `z_mm`: base frame position, mm. `roll_deg`, `pitch_deg`, `yaw_deg`: our
//!   URDF roll / pitch / yaw, deg, all three or none; without them the orientation the TCP had
//!   when the step started is held.
//! - Expressions: numbers (`2`, `0.5`, `.5`), `t`, the constants `pi`, `tau`, `e` (also `PI`,
//!   `TAU`, `E`), `+ - * / ^` (`^` is a power, written `(-2)^2` for a negative base; unary minus
//!   binds tighter than `^`), parentheses, and the functions `sin cos tan asin acos atan sinh
//!   cosh tanh asinh acosh atanh sqrt cbrt exp ln log (natural) log2 log10 abs signum floor
//!   ceil round trunc fract` of one argument and `atan2(y, x) min(a, b) max(a, b)`. Angles in
//!   the functions are radians. Evaluated with the `exmex` crate (MIT / Apache-2.0); the
//!   syntax is checked here first so an error names its column.
//! - The expressions are evaluated every 1 / `sample_rate_hz` s and at the end of each piece;
//!   the compiler follows those points in time (interpolated at the run period, IK in the
//!   start branch). The first point must be where the TCP is when the step starts: there is no
//!   automatic approach move (put a `move_l` or `move_pose` to it before the step), so the arm
//!   never moves somewhere the program does not say.
//!
//! Errors name the piece (1-based), the axis and the expression, and the column of a syntax
//! error: `piece 2, y(t) = "3*t +": column 6: the expression ends where a number, t, a
//! function or '(' is expected`. A value that is not a finite number names the time.

use exmex::prelude::*;
use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use super::PoseMm;

/// The longest expression accepted, characters.
pub const MAX_EXPRESSION_CHARS: usize = 500;
/// The deepest nesting of parentheses accepted.
pub const MAX_NESTING: usize = 32;
/// The most pieces one function may have.
pub const MAX_PIECES: usize = 1000;
/// The most points one function may be sampled to.
pub const MAX_FUNCTION_SAMPLES: usize = 1_000_000;
/// Sample rates accepted, Hz.
pub const SAMPLE_RATE_RANGE_HZ: (f64, f64) = (1.0, 1000.0);
/// The longest function, s.
pub const MAX_FUNCTION_S: f64 = 3600.0;
/// How far a piece may start from where the one before ends, mm.
pub const JOIN_TOLERANCE_MM: f64 = 0.1;
/// How far a piece's orientation may start from where the one before ends, deg.
pub const JOIN_TOLERANCE_DEG: f64 = 0.1;

/// One piece: expressions of its local time `t` (0 … `duration_s`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimePiece {
    /// How long the piece lasts, s.
    pub duration_s: f64,
    /// x(t), mm.
    pub x_mm: String,
    /// y(t), mm.
    pub y_mm: String,
    /// z(t), mm.
    pub z_mm: String,
    /// roll(t), deg (all three angles or none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub roll_deg: Option<String>,
    /// pitch(t), deg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pitch_deg: Option<String>,
    /// yaw(t), deg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw_deg: Option<String>,
}

impl TimePiece {
    /// A piece of position expressions only (the orientation is held).
    pub fn position(duration_s: f64, x_mm: &str, y_mm: &str, z_mm: &str) -> Self {
        Self {
            duration_s,
            x_mm: x_mm.into(),
            y_mm: y_mm.into(),
            z_mm: z_mm.into(),
            roll_deg: None,
            pitch_deg: None,
            yaw_deg: None,
        }
    }
}

/// Why a time function cannot be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TimeFnError {
    /// An expression that does not parse.
    #[error("piece {piece}, {axis}(t) = \"{expression}\": column {column}: {message}")]
    Syntax {
        /// 1-based piece.
        piece: usize,
        /// `x`, `y`, `z`, `roll`, `pitch` or `yaw`.
        axis: &'static str,
        /// The expression as written.
        expression: String,
        /// 1-based character column of the mistake.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// An expression whose value is not a finite number at some time.
    #[error("piece {piece}, {axis}(t) = \"{expression}\": {message} at t = {t_s} s")]
    Value {
        /// 1-based piece.
        piece: usize,
        /// The axis.
        axis: &'static str,
        /// The expression as written.
        expression: String,
        /// Local time, s.
        t_s: f64,
        /// What is wrong.
        message: String,
    },
    /// A piece that is wrong as a whole (duration, angles, join).
    #[error("piece {piece}: {message}")]
    Piece {
        /// 1-based piece.
        piece: usize,
        /// What is wrong.
        message: String,
    },
    /// The function as a whole (rate, number of pieces or samples).
    #[error("{0}")]
    Function(String),
}

/// One parsed expression.
struct Compiled {
    expr: FlatEx<f64>,
    /// The value of each variable of `expr` (in its order), `None` for `t`.
    constants: Vec<Option<f64>>,
}

impl Compiled {
    fn eval(&self, t_s: f64) -> Result<f64, String> {
        let vars: Vec<f64> = self.constants.iter().map(|c| c.unwrap_or(t_s)).collect();
        let v = self.expr.eval(&vars).map_err(|e| e.msg().to_string())?;
        if v.is_finite() { Ok(v) } else { Err(format!("the value is {v}, not a finite number")) }
    }
}

/// The names an expression may use besides numbers and functions, with their values (`None`:
/// the time).
const NAMES: [(&str, Option<f64>); 7] = [
    ("t", None),
    ("pi", Some(std::f64::consts::PI)),
    ("PI", Some(std::f64::consts::PI)),
    ("tau", Some(std::f64::consts::TAU)),
    ("TAU", Some(std::f64::consts::TAU)),
    ("e", Some(std::f64::consts::E)),
    ("E", Some(std::f64::consts::E)),
];

/// Functions of one argument.
const UNARY: [&str; 26] = [
    "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "sqrt", "cbrt",
    "exp", "ln", "log", "log2", "log10", "abs", "signum", "floor", "ceil", "round", "trunc", "fract",
];
/// Functions of two arguments, `f(a, b)`.
const BINARY: [&str; 3] = ["atan2", "min", "max"];

/// Checks the syntax of `text` and parses it. Error: (1-based column, message).
fn compile_expression(text: &str) -> Result<Compiled, (usize, String)> {
    syntax::check(text, &NAMES.map(|(n, _)| n), &UNARY, &BINARY)?;
    // every function name above is one of exmex's float operators; `pi`, `tau` and `t` are
    // exmex variables given their values here
    let expr = FlatEx::<f64>::parse(text).map_err(|e| (1, e.msg().to_string()))?;
    let constants = expr
        .var_names()
        .iter()
        .map(|name| match NAMES.iter().find(|(n, _)| n == name) {
            Some((_, value)) => Ok(*value),
            None => Err((1, format!("unknown name \"{name}\""))),
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Compiled { expr, constants })
}

/// A time function ready to evaluate: every expression parsed.
pub struct TimeFunction {
    pieces: Vec<CompiledPiece>,
    sample_rate_hz: f64,
}

struct CompiledPiece {
    duration_s: f64,
    /// x, y, z, then roll, pitch, yaw when given.
    axes: Vec<(&'static str, String, Compiled)>,
}

/// A timed TCP point: time from the function's start, s, and the pose.
pub type TimedPose = (f64, Isometry3<f64>);

impl TimeFunction {
    /// Parses every expression and checks the durations and the rate.
    pub fn new(pieces: &[TimePiece], sample_rate_hz: f64) -> Result<Self, TimeFnError> {
        let (lo, hi) = SAMPLE_RATE_RANGE_HZ;
        if !(sample_rate_hz.is_finite() && (lo..=hi).contains(&sample_rate_hz)) {
            return Err(TimeFnError::Function(format!(
                "sample_rate_hz must lie in {lo}–{hi} Hz, got {sample_rate_hz}"
            )));
        }
        if pieces.is_empty() {
            return Err(TimeFnError::Function("a time function needs at least one piece".into()));
        }
        if pieces.len() > MAX_PIECES {
            return Err(TimeFnError::Function(format!(
                "a time function has at most {MAX_PIECES} pieces, got {}",
                pieces.len()
            )));
        }
        let mut total_s = 0.0;
        let mut out = Vec::with_capacity(pieces.len());
        for (i, p) in pieces.iter().enumerate() {
            let piece = i + 1;
            if !(p.duration_s.is_finite() && p.duration_s > 0.0) {
                return Err(TimeFnError::Piece {
                    piece,
                    message: format!("duration_s must be a number above 0, got {}", p.duration_s),
                });
            }
            total_s += p.duration_s;
            let mut texts: Vec<(&'static str, &String)> = vec![("x", &p.x_mm), ("y", &p.y_mm), ("z", &p.z_mm)];
            match (&p.roll_deg, &p.pitch_deg, &p.yaw_deg) {
                (Some(r), Some(pi), Some(y)) => texts.extend([("roll", r), ("pitch", pi), ("yaw", y)]),
                (None, None, None) => {}
                _ => {
                    return Err(TimeFnError::Piece {
                        piece,
                        message: "give roll_deg, pitch_deg and yaw_deg together, or none of them".into(),
                    });
                }
            }
            let mut axes = Vec::with_capacity(texts.len());
            for (axis, text) in texts {
                let compiled = compile_expression(text).map_err(|(column, message)| TimeFnError::Syntax {
                    piece,
                    axis,
                    expression: text.clone(),
                    column,
                    message,
                })?;
                axes.push((axis, text.clone(), compiled));
            }
            out.push(CompiledPiece { duration_s: p.duration_s, axes });
        }
        if total_s > MAX_FUNCTION_S {
            return Err(TimeFnError::Function(format!(
                "the pieces last {total_s} s together; a time function lasts at most {MAX_FUNCTION_S} s"
            )));
        }
        let samples = total_s * sample_rate_hz + pieces.len() as f64 + 1.0;
        if samples > MAX_FUNCTION_SAMPLES as f64 {
            return Err(TimeFnError::Function(format!(
                "{total_s} s at {sample_rate_hz} Hz is more than {MAX_FUNCTION_SAMPLES} points: lower the rate"
            )));
        }
        Ok(Self { pieces: out, sample_rate_hz })
    }

    /// How long the function lasts, s.
    pub fn duration_s(&self) -> f64 {
        self.pieces.iter().map(|p| p.duration_s).sum()
    }

    /// The function's points in time order, from t = 0 to its end: every 1 / rate within each
    /// piece and at each piece's end. Where no angles are given the orientation of `start` is
    /// held. Each piece must begin where the one before ends.
    pub fn sample(&self, start: &Isometry3<f64>) -> Result<Vec<TimedPose>, TimeFnError> {
        let hold_rpy_deg = PoseMm::from_isometry(start).rpy_deg;
        let mut out: Vec<TimedPose> = Vec::new();
        let mut piece_start_s = 0.0;
        let step_s = 1.0 / self.sample_rate_hz;
        for (i, p) in self.pieces.iter().enumerate() {
            // a duration of a whole number of samples gives no extra point for rounding
            let n = (p.duration_s / step_s - 1e-9).ceil().max(1.0) as usize;
            for k in 0..=n {
                let t = (k as f64 * step_s).min(p.duration_s);
                let pose = self.pose_at(i, t, hold_rpy_deg)?;
                match out.last() {
                    Some((_, prev)) if k == 0 => check_join(i + 1, prev, &pose)?,
                    Some((last_s, _)) if piece_start_s + t <= *last_s => {}
                    _ => out.push((piece_start_s + t, pose)),
                }
            }
            piece_start_s += p.duration_s;
        }
        Ok(out)
    }

    fn pose_at(&self, piece: usize, t_s: f64, hold_rpy_deg: [f64; 3]) -> Result<Isometry3<f64>, TimeFnError> {
        let p = &self.pieces[piece];
        let mut v = [0.0; 6];
        for (k, (axis, text, c)) in p.axes.iter().enumerate() {
            v[k] = c.eval(t_s).map_err(|message| TimeFnError::Value {
                piece: piece + 1,
                axis,
                expression: text.clone(),
                t_s,
                message,
            })?;
            let limit = if k < 3 { super::compile::MAX_POSITION_MM } else { 1.0e6 };
            if v[k].abs() > limit {
                return Err(TimeFnError::Value {
                    piece: piece + 1,
                    axis,
                    expression: text.clone(),
                    t_s,
                    message: format!("the value {} is beyond ±{limit}", v[k]),
                });
            }
        }
        let rpy_deg = if p.axes.len() == 6 { [v[3], v[4], v[5]] } else { hold_rpy_deg };
        Ok(PoseMm { position_mm: [v[0], v[1], v[2]], rpy_deg }.isometry())
    }
}

fn check_join(piece: usize, prev: &Isometry3<f64>, next: &Isometry3<f64>) -> Result<(), TimeFnError> {
    let gap_mm = (next.translation.vector - prev.translation.vector).norm() * 1000.0;
    let turn_deg = prev.rotation.angle_to(&next.rotation).to_degrees();
    if gap_mm > JOIN_TOLERANCE_MM || turn_deg > JOIN_TOLERANCE_DEG {
        return Err(TimeFnError::Piece {
            piece,
            message: format!(
                "starts {gap_mm:.2} mm and {turn_deg:.2}° from where piece {} ends (at most {JOIN_TOLERANCE_MM} mm \
                 and {JOIN_TOLERANCE_DEG}°)",
                piece - 1
            ),
        });
    }
    Ok(())
}

mod syntax;

#[cfg(test)]
mod tests;
