//! fragkit-report: what a run of cases yields, without the GPU that ran them. Outcomes and case
//! records, the run's adapter and provenance, the sinks records go to, the known issues that
//! explain failures, and the statistics that judge GPU times. The results store, comparison,
//! HTML, JUnit and GitHub outputs build on this crate alone; the GPU kit (`fragkit`) produces it.

pub mod adapter;
pub mod expectations;
pub mod noise;
pub mod param_value;
pub mod plot_data;
pub mod readable;
pub mod report;
pub mod run_info;
pub mod sink;
pub mod skips;
pub mod summary;

pub use adapter::AdapterDescription;
pub use report::{CaseRecord, Report, ReportedOutcome};
pub use sink::{Shard, Sink};
