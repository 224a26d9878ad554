//! The case harness: cases with parameters and requirements, the runner that runs each case
//! (`runner`), the run loop that feeds every record to its sinks (`run`), and the supervisor
//! that runs a case list in child processes so that a crash or a hang costs one case
//! (`supervise`), several at once with the timed cases alone (`case_lock`). What a run yields —
//! records, outcomes, sinks, known issues — is the report model, `fragkit_report`.

pub mod bug_report;
pub mod capability;
pub mod case;
pub mod case_lock;
pub mod child_process;
pub mod params;
pub mod registry;
pub mod reproduce;
pub mod run;
pub mod runner;
pub mod stream;
pub mod suite;
pub mod supervise;
pub mod sweep;
pub mod verdict;

pub use case::{Case, Ctx, Outcome};
pub use params::{ParamKind, ParamSpec, Sweep, SweepRange};
pub use verdict::Verdict;
