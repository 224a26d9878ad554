//! Order-independent transparency by stochastic alpha-to-coverage, with the alternatives it is
//! measured against: plain alpha-to-coverage, an exact sample-mask pattern, sorted blending,
//! weighted blended OIT, depth peeling, and an exact CPU composite.

pub mod filter;
pub mod fragment_random;
pub mod methods;
pub mod pictures;
pub mod reference;
pub mod report;
pub mod run;
pub mod scene;
pub mod stochastic;
