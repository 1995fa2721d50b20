//! A body held in place: the points its held ends keep, and how far they move.
//!
//! Turning angles drop each frame's translation and rotation; a body whose ends hold points
//! (a clamped end two, a pinned end one, on the model's N points) is held in the lab, so its
//! frames are observed with the held points of one reference frame, the animal's first usable
//! one. A reference frame's noise is a constant offset of the modal coordinates, which the
//! means remove; each frame's own held points would turn the body by their noise every frame.
//! Whether the ends are held is the model's claim, checked by [`Movement`]: the held ends'
//! rms displacement from the reference frame over the whole midline's.

use super::observe::on_points;
use super::project::{tail_first, FrameError, Projector};
use super::InputKind;

/// The points a body's held ends keep in place (a clamped end two, a pinned end one), on the
/// model's N points in its order (tail first), taken from one reference frame and put into
/// every frame before its turning angles: a body held in the lab (a head in agarose, a worm in
/// a trap) has them fixed there, so their tracking noise is left out rather than turning
/// every frame's body frame (a clamped head's first segment set the lowest mode's frame: its
/// tracking noise reached that coordinate with 10⁴ times the variance it has in the lab's).
#[derive(Debug, Clone, PartialEq)]
pub struct HeldPoints {
    /// The held points at the tail (s = 0), then those at the head.
    tail: Vec<(f64, f64)>,
    head: Vec<(f64, f64)>,
}

impl HeldPoints {
    /// The held points (`counts` at tail and head) of a frame of midline `values` (tail first)
    /// resampled to `n` points; `None` when nothing is held or the frame is unusable.
    pub(crate) fn of(values: &[f64], n: usize, counts: (usize, usize)) -> Option<HeldPoints> {
        if counts == (0, 0) || counts.0 + counts.1 > n {
            return None;
        }
        let pts = on_points(values, n).ok()?;
        if pts.iter().any(|p| !(p.0.is_finite() && p.1.is_finite())) {
            return None;
        }
        Some(HeldPoints {
            tail: pts[..counts.0].to_vec(),
            head: pts[n - counts.1..].to_vec(),
        })
    }

    /// The held point at index `i` of `n` (tail first), if `i` is held.
    pub(crate) fn at(&self, i: usize, n: usize) -> Option<(f64, f64)> {
        if i < self.tail.len() {
            return self.tail.get(i).copied();
        }
        let from = n.checked_sub(self.head.len())?;
        (i >= from)
            .then(|| self.head.get(i - from).copied())
            .flatten()
    }

    /// Put the held points into `pts` (N points, tail first).
    pub(crate) fn hold(&self, pts: &mut [(f64, f64)]) {
        let n = pts.len();
        if self.tail.len() + self.head.len() > n {
            return;
        }
        pts[..self.tail.len()].copy_from_slice(&self.tail);
        pts[n - self.head.len()..].copy_from_slice(&self.head);
    }
}

/// How far the held ends of an animal move from its reference frame, against the whole
/// midline: Σ|pₑ − rₑ|² over the tracked end points at held ends, and Σ mean_k |p_k − r_k|²,
/// over frames.
#[derive(Debug, Clone, Default)]
pub struct Movement {
    /// The reference frame's values, as read.
    reference: Vec<f64>,
    /// The tracked points at held ends, as read.
    ends: Vec<usize>,
    held: f64,
    body: f64,
}

/// The share of the midline's movement above which a held end is said to move.
pub const MOVING_SHARE: f64 = 0.25;

impl Movement {
    /// The movement of midlines like `reference` (as read: head first when `head_first`)
    /// whose ends (tail, head) are held.
    pub(crate) fn new(reference: &[f64], held: (bool, bool), head_first: bool) -> Movement {
        let last = (reference.len() / 2).saturating_sub(1);
        let (tail, head) = if head_first { (last, 0) } else { (0, last) };
        let ends = [(held.0, tail), (held.1, head)]
            .iter()
            .filter(|(h, _)| *h)
            .map(|&(_, i)| i)
            .collect();
        Movement {
            reference: reference.to_vec(),
            ends,
            ..Movement::default()
        }
    }

    /// Add one frame (as wide as the reference; others are skipped).
    pub(crate) fn frame(&mut self, values: &[f64]) {
        let k = values.len() / 2;
        if values.len() != self.reference.len() || k < 2 || self.ends.is_empty() {
            return;
        }
        let away = |i: usize| {
            let (dx, dy) = (
                values[2 * i] - self.reference[2 * i],
                values[2 * i + 1] - self.reference[2 * i + 1],
            );
            dx * dx + dy * dy
        };
        let held = self.ends.iter().map(|&i| away(i)).sum::<f64>() / self.ends.len() as f64;
        let body = (0..k).map(away).sum::<f64>() / k as f64;
        if (held + body).is_finite() {
            self.held += held;
            self.body += body;
        }
    }

    /// Add another animal's.
    pub(crate) fn absorb(&mut self, other: &Movement) {
        self.held += other.held;
        self.body += other.body;
    }

    /// The held ends' rms displacement over the midline's (`None` before any movement).
    pub fn share(&self) -> Option<f64> {
        let s = (self.held / self.body).sqrt();
        (self.body > 0.0 && s.is_finite()).then_some(s)
    }

    /// The warning a recording whose held ends move gets, if they do.
    pub fn warning(&self) -> Option<String> {
        let s = self.share().filter(|&s| s > MOVING_SHARE)?;
        Some(format!(
            "the model holds an end of this body in place, but the recording's held end moves: its rms displacement from the first frame is {:.0} % of the whole midline's (at most {:.0} % for a held end); the frames are observed with the first frame's held points, so this fit is not of a held body: a model with that end free fits such a recording",
            100.0 * s,
            100.0 * MOVING_SHARE
        ))
    }
}

impl Projector {
    /// Whether the observed field holds points at an end (midlines): then every frame is
    /// observed with the held points of its animal's reference frame ([`Projector::hold`]).
    pub fn holds(&self) -> bool {
        self.held_counts != (0, 0)
    }

    /// The movement check of an animal whose first usable frame is `values` (`None` when no
    /// point is held).
    pub(crate) fn movement(&self, values: &[f64], head_first: bool) -> Option<Movement> {
        let ends = (self.held_counts.0 > 0, self.held_counts.1 > 0);
        (self.holds() && self.kind == InputKind::Midline)
            .then(|| Movement::new(values, ends, head_first))
    }

    /// Whether the held points of a reference frame are set.
    pub fn holding(&self) -> bool {
        self.held.is_some()
    }

    /// Take the held points of every following frame from this frame of `values` (a new
    /// animal's first usable frame); nothing when no point is held or the frame is unusable.
    pub fn hold(&mut self, values: &[f64], head_first: bool) {
        if !self.holds() || values.len() != 2 * self.input_points {
            return;
        }
        let values = tail_first(self.kind, values, head_first);
        self.held = HeldPoints::of(&values, self.points, self.held_counts);
    }

    /// [`Projector::modal`] of a shape drawn on the straight body at rest (its held points).
    pub(super) fn modal_at_rest(&self, values: &[f64]) -> Result<Vec<f64>, FrameError> {
        self.modal_held(values, self.grid().rest().as_ref())
    }
}
