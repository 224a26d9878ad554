//! fragkit-results: what is done with runs once they are made, by any suite written on fragkit.
//! The run database (SQLite by default, PostgreSQL by URL) behind compare and history, baselines
//! and snapshots to judge a run against, and the HTML, JUnit and GitHub outputs, as sinks of the
//! report model (`fragkit_report`). Nothing here opens a GPU.

pub mod baseline;
pub mod compare;
pub mod database;
pub mod github;
pub mod html;
pub mod junit;
pub mod markup;
pub mod plot;
pub mod snapshot;
