//! `fault.*`: fault injection, run only when named (`fragkit check 'fault.*'`). Each case breaks
//! the GPU or its process on purpose and therefore ends `fail`, `crash` or `timeout`: what they
//! check is the runner around them — the fault is captured in that case's record with its
//! message, and the run goes on (on a new device after a loss, in a new process after a crash or
//! a hang or running out of memory). `cases/tests/cli.rs` runs them between ordinary cases and
//! checks the report. `fault.leak` is a soak with a leak in it: the soaks' leak check must fail
//! it (`cases/tests/soak.rs`).

fragkit::cases! {
    validation_error: CASE;
    device_loss: CASE;
    abort: CASE;
    segfault: CASE;
    hang: CASE;
    out_of_memory: CASE;
    leak: CASE;
}
