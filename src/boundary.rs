//! Boundary conditions, from the model file to the generated code: a field is periodic or has
//! one [`End`] at each end. Everything a boundary decides about a grid (held points, unknowns,
//! the least number of points, the zero modes) is a method here, so that no other module
//! matches boundaries by name.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::markup::clip;

/// The condition at one end of a non-periodic field.
///
/// An end holds some of the field's lowest derivatives at zero and leaves the rest natural (no
/// force, no moment): on the grid a held derivative is a held point, so an end of stencil order k
/// holds [`End::held`] points (value: the end point; slope: the next one as well).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum End {
    /// Nothing held: no force or moment (Neumann).
    Free,
    /// The value held, no moment (simply supported).
    Pinned,
    /// Value and slope held (a k = 1 field has no slope condition: the value only).
    Clamped,
}

impl End {
    /// Every end kind, in the order of the docs.
    pub const ALL: [End; 3] = [End::Free, End::Pinned, End::Clamped];

    /// How many derivatives (0 = value, 1 = slope) this end holds for a stencil of order `k`: a
    /// 2k-order equation takes k conditions per end, so at most k of them can be held.
    pub fn held(self, k: u32) -> usize {
        let k = k as usize;
        match self {
            End::Free => 0,
            End::Pinned => 1.min(k),
            End::Clamped => 2.min(k),
        }
    }

    /// Lower-case name, as in model files.
    pub fn name(self) -> &'static str {
        match self {
            End::Free => "free",
            End::Pinned => "pinned",
            End::Clamped => "clamped",
        }
    }

    fn parse(word: &str) -> Option<End> {
        End::ALL.into_iter().find(|e| e.name() == word)
    }
}

/// Boundary condition of a field: head and tail tied together, or one [`End`] each.
///
/// In a model file: one word for both ends (`"periodic"`, `"free"`, `"pinned"`, `"clamped"`) or a
/// table `{ head = "clamped", tail = "free" }`. Arc length runs from the tail (point 0) to the
/// head (point N − 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Boundary {
    /// Head and tail tied together (the larva's visceral piston for the axial field).
    Periodic,
    /// Each end on its own.
    Ends {
        /// The end at s = 0 (point 0).
        tail: End,
        /// The end at s = L (point N − 1).
        head: End,
    },
}

impl Boundary {
    /// Both ends free.
    pub const FREE: Boundary = Boundary::both(End::Free);
    /// Both ends pinned.
    pub const PINNED: Boundary = Boundary::both(End::Pinned);
    /// Both ends clamped.
    pub const CLAMPED: Boundary = Boundary::both(End::Clamped);

    /// The same end at head and tail.
    pub const fn both(end: End) -> Boundary {
        Boundary::Ends {
            tail: end,
            head: end,
        }
    }

    /// Held points at (tail, head) for a stencil of order `k`; none for periodic fields.
    pub fn held(self, k: u32) -> (usize, usize) {
        match self {
            Boundary::Periodic => (0, 0),
            Boundary::Ends { tail, head } => (tail.held(k), head.held(k)),
        }
    }

    /// Name for reports: `periodic`, `free`, … or `head clamped, tail free`.
    pub fn name(self) -> String {
        match self {
            Boundary::Periodic => "periodic".into(),
            Boundary::Ends { tail, head } if tail == head => tail.name().into(),
            Boundary::Ends { tail, head } => {
                format!("head {}, tail {}", head.name(), tail.name())
            }
        }
    }

    /// An identifier-safe name: `periodic`, `free`, … or `head_clamped_tail_free`.
    pub fn slug(self) -> String {
        self.name().replace(", ", "_").replace(' ', "_")
    }

    /// Number of unknowns on `points` points for a stencil of order `k`: a periodic field ties
    /// the head to the tail, held ends drop their held points.
    pub fn unknowns(self, k: u32, points: usize) -> usize {
        match self {
            Boundary::Periodic => points.saturating_sub(1),
            Boundary::Ends { .. } => {
                let (tail, head) = self.held(k);
                points.saturating_sub(tail + head)
            }
        }
    }

    /// The least number of points a stencil of order `k` needs: one whole stencil and at least
    /// one unknown (two around a ring).
    pub fn min_points(self, k: u32) -> usize {
        match self {
            Boundary::Periodic => k as usize + 2,
            Boundary::Ends { .. } => {
                let (tail, head) = self.held(k);
                (k as usize + 1).max(tail + head + 1)
            }
        }
    }

    /// Number of structural zero modes of the k-th difference operator with this boundary:
    /// constants around a ring, polynomials of degree < k less one per held point otherwise.
    pub fn nullity(self, k: u32) -> usize {
        match self {
            Boundary::Periodic => 1,
            Boundary::Ends { .. } => {
                let (tail, head) = self.held(k);
                (k as usize).saturating_sub(tail + head)
            }
        }
    }

    /// Read one word or a `{ head, tail }` table.
    fn from_spec(spec: BoundarySpec) -> Result<Boundary, BoundaryError> {
        let end = |word: &str, which: &'static str| {
            End::parse(word).ok_or_else(|| BoundaryError::End {
                which,
                word: word.to_string(),
            })
        };
        match spec {
            BoundarySpec::Word(w) if w == "periodic" => Ok(Boundary::Periodic),
            BoundarySpec::Word(w) => End::parse(&w)
                .map(Boundary::both)
                .ok_or(BoundaryError::Word(w)),
            BoundarySpec::Ends { head, tail } => Ok(Boundary::Ends {
                tail: end(&tail, "tail")?,
                head: end(&head, "head")?,
            }),
        }
    }
}

/// A boundary a model file names that does not exist.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum BoundaryError {
    /// Not one of the boundary words.
    #[error("boundary {} is not one of periodic, free, pinned, clamped", clip(.0))]
    Word(String),
    /// Not one of the end words.
    #[error("{which} end {} is not one of free, pinned, clamped{}", clip(.word), if .word == "periodic" { " (periodic ties both ends: write boundary = \"periodic\")" } else { "" })]
    End {
        /// `head` or `tail`.
        which: &'static str,
        /// The word given.
        word: String,
    },
}

/// A boundary as written in a model file.
#[derive(Serialize)]
#[serde(untagged)]
enum BoundarySpec {
    Word(String),
    Ends { head: String, tail: String },
}

impl Serialize for Boundary {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            Boundary::Periodic => BoundarySpec::Word("periodic".into()),
            Boundary::Ends { tail, head } if tail == head => BoundarySpec::Word(tail.name().into()),
            Boundary::Ends { tail, head } => BoundarySpec::Ends {
                head: head.name().into(),
                tail: tail.name().into(),
            },
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Boundary {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let value = toml::Value::deserialize(d)?;
        let spec = match value {
            toml::Value::String(w) => BoundarySpec::Word(w),
            toml::Value::Table(mut t) => {
                let mut take = |key: &str| match t.remove(key) {
                    Some(toml::Value::String(w)) => Ok(w),
                    Some(_) => Err(format!("boundary {key} must be a string")),
                    None => Err(format!("boundary table needs `{key}`")),
                };
                let (head, tail) = (take("head"), take("tail"));
                if let Some(extra) = t.keys().next() {
                    return Err(serde::de::Error::custom(format!(
                        "boundary table has unknown key `{extra}` (expected head and tail)"
                    )));
                }
                BoundarySpec::Ends {
                    head: head.map_err(serde::de::Error::custom)?,
                    tail: tail.map_err(serde::de::Error::custom)?,
                }
            }
            _ => {
                return Err(serde::de::Error::custom(
                    "boundary must be a word or a table { head = \"…\", tail = \"…\" }",
                ))
            }
        };
        Boundary::from_spec(spec).map_err(serde::de::Error::custom)
    }
}

impl fmt::Display for Boundary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}
