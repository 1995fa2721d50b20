//! One theory value: a model at an order on N points with its scales, and the modes (with
//! shapes) of every field, computed once. Every stage after the modal solver borrows it, so no
//! behaviour, statistic or figure recomputes modes another stage already has.

use crate::modal::{field_modes, FieldModes, ModesError, Params};
use crate::model::{Model, Role, RoleError};

/// A model, its order and scales, and the modes of every field on `points` points.
#[derive(Debug, Clone)]
pub struct Theory {
    /// The body.
    pub model: Model,
    /// Order of the expansion the operators come from.
    pub order: u32,
    /// Points along the body.
    pub points: usize,
    /// Frequency and damping scales.
    pub params: Params,
    /// Every field's modes, all of them, with shapes, in model field order.
    pub modes: Vec<FieldModes>,
}

impl Theory {
    /// Derive the operators of `model` at `order` and every field's modes on `points` points.
    pub fn new(
        model: Model,
        order: u32,
        points: usize,
        params: Params,
    ) -> Result<Theory, ModesError> {
        let modes = field_modes(&model, order, points, &params, None, true)?;
        Ok(Theory {
            model,
            order,
            points,
            params,
            modes,
        })
    }

    /// The index of the field with `role`, or an error naming the role and `command`.
    pub fn role(&self, role: Role, command: &str) -> Result<usize, RoleError> {
        self.model.role_index(role, command)
    }

    /// The same theory with every field undamped (ζ = 0): the conservative dynamics.
    pub fn undamped(&self) -> Theory {
        let mut t = self.clone();
        t.modes = t.modes.iter().map(|f| f.with_zeta(0.0)).collect();
        t
    }
}
