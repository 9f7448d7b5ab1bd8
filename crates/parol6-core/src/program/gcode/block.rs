//! One line's words sorted into codes by modal group and parameter words, with "used" marks so
//! that a word nobody reads is an error.

use super::GcodeError;
use super::lexer::Word;

/// The axis letters, in pose order.
pub(crate) const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// Modal groups: at most one code of each on a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Group {
    /// G0 G1 G2 G3 and the one-line G4 G10 G28.
    Motion,
    Plane,
    Units,
    Distance,
    Work,
    Path,
}

/// One line's words, sorted out.
pub(crate) struct Block {
    pub line: usize,
    codes: Vec<(Group, u32, Word)>,
    pub m: Option<(u32, Word)>,
    /// Parameter words in line order, with "used" marks.
    pub params: Vec<(Word, bool)>,
}

impl Block {
    pub(crate) fn sort(line: usize, words: Vec<Word>) -> Result<Self, GcodeError> {
        let mut b = Block { line, codes: Vec::new(), m: None, params: Vec::new() };
        for w in words {
            let code = (w.value.fract() == 0.0 && (0.0..1000.0).contains(&w.value)).then_some(w.value as u32);
            match w.letter {
                'G' => {
                    let group = match code {
                        Some(0..=4 | 10 | 28) => Group::Motion,
                        Some(17..=19) => Group::Plane,
                        Some(20 | 21) => Group::Units,
                        Some(54..=59) => Group::Work,
                        Some(61 | 64) => Group::Path,
                        Some(90 | 91) => Group::Distance,
                        _ => return Err(GcodeError::at_word(line, &w.text, "unsupported G code")),
                    };
                    if let Some((_, _, other)) = b.codes.iter().find(|(g, _, _)| *g == group) {
                        return Err(GcodeError::at_word(
                            line,
                            &w.text,
                            format!(
                                "conflicts with \"{}\" on the same line (one code of a group per line)",
                                other.text
                            ),
                        ));
                    }
                    b.codes.push((group, code.unwrap_or(0), w));
                }
                'M' => {
                    let Some(code @ (0..=5 | 30)) = code else {
                        return Err(GcodeError::at_word(line, &w.text, "unsupported M code"));
                    };
                    if let Some((_, other)) = &b.m {
                        return Err(GcodeError::at_word(
                            line,
                            &w.text,
                            format!("one M code per line (\"{}\" is already on it)", other.text),
                        ));
                    }
                    b.m = Some((code, w));
                }
                'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | 'I' | 'J' | 'K' | 'R' | 'F' | 'P' | 'S' | 'L' => {
                    if let Some((other, _)) = b.params.iter().find(|(p, _)| p.letter == w.letter) {
                        return Err(GcodeError::at_word(
                            line,
                            &w.text,
                            format!("{} appears twice on the line (\"{}\" first)", w.letter, other.text),
                        ));
                    }
                    b.params.push((w, false));
                }
                'T' => {
                    return Err(GcodeError::at_word(
                        line,
                        &w.text,
                        "tool changes (T) are not supported: the tool is chosen in PAROL6 Studio",
                    ));
                }
                _ => return Err(GcodeError::at_word(line, &w.text, "unsupported word")),
            }
        }
        Ok(b)
    }

    pub(crate) fn code(&self, group: Group) -> Option<(u32, Word)> {
        self.codes.iter().find(|(g, _, _)| *g == group).map(|(_, c, w)| (*c, w.clone()))
    }

    pub(crate) fn has(&self, letter: char) -> bool {
        self.params.iter().any(|(w, _)| w.letter == letter)
    }

    /// Takes (marks used) the word of `letter`.
    pub(crate) fn take(&mut self, letter: char) -> Option<Word> {
        let (w, used) = self.params.iter_mut().find(|(w, _)| w.letter == letter)?;
        *used = true;
        Some(w.clone())
    }

    pub(crate) fn take_axes(&mut self) -> [Option<Word>; 6] {
        AXES.map(|a| self.take(a))
    }

    /// The first word nobody used, as an error.
    pub(crate) fn leftover(&self) -> Result<(), GcodeError> {
        let Some((w, _)) = self.params.iter().find(|(_, used)| !used) else { return Ok(()) };
        let why = match w.letter {
            'I' | 'J' | 'K' | 'R' => "I, J, K and R are only used by G2 and G3",
            'P' => "P is only used by G4, G10, G64 and M3/M4/M5",
            'S' => "S is only used by G4 (dwell seconds); there is no spindle",
            'L' => "L is only used by G10",
            _ => "axis words need a motion code (G0, G1, G2 or G3) on the line or active",
        };
        Err(GcodeError::at_word(self.line, &w.text, why))
    }
}
