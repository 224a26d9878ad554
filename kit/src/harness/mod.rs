//! The case harness: cases with parameters and requirements, outcomes, the expectations file of
//! known driver issues, the runner that isolates each case, the run loop that feeds every record
//! to its sinks, and the JSON and JUnit reports.

pub mod baseline;
pub mod capability;
pub mod case;
pub mod compare;
pub mod database;
pub mod diagnostics;
pub mod expectations;
pub mod github;
pub mod html;
pub mod junit;
pub mod markup;
pub mod matrix;
pub mod noise;
pub mod params;
pub mod readable;
pub mod report;
pub mod run;
pub mod run_info;
pub mod runner;
pub mod snapshot;
pub mod stream;
pub mod sweep;

pub use case::{Case, Ctx, Outcome};
pub use params::{ParamKind, ParamSpec};
pub use sweep::{Sweep, SweepRange};
