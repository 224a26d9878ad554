//! fragkit's render cases, one per file under `<area>/`, and the registry the CLI and the tests
//! share.

use std::sync::OnceLock;

use fragkit::harness::Case;
use fragkit::harness::registry::join;

pub mod cbr;
pub mod cps;
pub mod fault;
pub mod kit;
pub mod oit;
pub mod soak;
pub mod texarray;

/// The known issues of this kit's cases on the adapters it was run on (cases/expectations.toml),
/// built in so that an installed `fragkit` needs no checkout.
pub const EXPECTATIONS: &str = include_str!("../expectations.toml");

/// Every case, in the order `fragkit check` runs them (opt-in ones only when named: see
/// `fragkit::harness::runner::OPT_IN`): each area's registry (its `mod.rs`), area by area.
pub fn all() -> &'static [Case] {
    static ALL: OnceLock<Vec<Case>> = OnceLock::new();
    join(&ALL, &[kit::CASES, cps::CASES, texarray::CASES, oit::CASES, cbr::CASES, fault::CASES, soak::CASES])
}
