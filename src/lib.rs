//! theory-search derives the effective physics of a soft, slender body from symmetry alone, as
//! Loveless et al. do by hand for the Drosophila larva: enumerate the candidate terms of the
//! Lagrangian and Rayleigh densities, strike out those that break a requirement, and keep each
//! field's lowest-order survivors.
//!
//! Data flows one way through the modules, in layers (docs/layout.md):
//! [`term`] → [`rules`], [`enumerate`], [`boundary`] → [`model`] → [`reduce`] → [`table`],
//! [`catalogue`], [`interaction`], [`parts`], [`discretise`], [`active`] → [`equations`], [`codegen`],
//! [`modal`] → [`artifacts`], [`theory`], [`dynamics`] → [`behaviour`] → [`fit`] → [`discover`] →
//! [`figures`] → [`cli`].
#![warn(missing_docs)]

pub mod active;
pub mod artifacts;
pub mod banded;
pub mod behaviour;
pub mod body;
pub mod boundary;
pub mod catalogue;
pub mod cli;
pub mod codegen;
pub mod compare;
pub mod discover;
pub mod discretise;
pub mod dynamics;
pub mod enumerate;
pub mod equations;
pub mod failure;
pub mod figures;
pub mod fit;
pub mod generated;
pub mod interaction;
pub mod jet;
pub mod markup;
pub mod modal;
pub mod model;
pub mod params;
pub mod parts;
pub mod recording;
pub mod reduce;
pub mod report;
pub mod rules;
pub mod statespace;
pub mod table;
pub mod term;
pub mod theory;
