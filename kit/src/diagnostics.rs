//! Log records of wgpu, naga and the drivers (EGL's "DRI2: failed to load driver" on a machine
//! without /dev/dri, a shader translation error behind a probe's expected failure) captured
//! instead of printed: the run loop files each case's records in its report entry, the records
//! before the first case in the report's own, and the terminal shows them with `-v` or under a
//! failing case. `RUST_LOG` set in the environment prints instead (env_logger), for developers.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

static CAPTURED: Mutex<Vec<String>> = Mutex::new(Vec::new());
/// Also print each record to stderr as it comes (`-v`).
static ECHO: AtomicBool = AtomicBool::new(false);
static LOGGER: CaptureLogger = CaptureLogger;

struct CaptureLogger;

impl log::Log for CaptureLogger {
    fn enabled(&self, metadata: &log::Metadata) -> bool {
        metadata.level() <= log::Level::Warn
    }

    fn log(&self, record: &log::Record) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let line = format!("{} {}: {}", record.level(), record.target(), record.args()).trim_end().to_owned();
        if ECHO.load(Ordering::Relaxed) {
            eprintln!("[{line}]");
        }
        CAPTURED.lock().unwrap_or_else(|e| e.into_inner()).push(line);
    }

    fn flush(&self) {}
}

/// Installs the capturing logger (warnings and errors; `echo` also prints them). Fails only if
/// another logger is installed.
pub fn capture(echo: bool) -> anyhow::Result<()> {
    ECHO.store(echo, Ordering::Relaxed);
    log::set_logger(&LOGGER).map_err(|e| anyhow::anyhow!("installing the log capture: {e}"))?;
    log::set_max_level(log::LevelFilter::Warn);
    Ok(())
}

/// The records captured since the last call, oldest first.
pub fn take() -> Vec<String> {
    std::mem::take(&mut *CAPTURED.lock().unwrap_or_else(|e| e.into_inner()))
}

/// How wgpu-hal relays a GL API error from the driver's debug output ("GLES: [API/Error] ID n :
/// message"), and how a record reads once a probe has claimed it.
const API_ERROR: &str = "[API/Error]";
const PROBED_API_ERROR: &str = "[API/Error, met by a probe]";

/// The GL API errors among `records` that no probe claimed, each distinct message once with its
/// count, in order of first appearance. Shader compiler messages are left out: wgpu reports the
/// pipeline they break as an error.
pub fn gl_api_errors(records: &[String]) -> Vec<String> {
    let mut counted: Vec<(String, usize)> = Vec::new();
    for record in records {
        let Some((_, message)) = record.split_once(API_ERROR) else {
            continue;
        };
        let message = message.split_once(" : ").map_or(message, |(_, text)| text).trim().to_owned();
        match counted.iter_mut().find(|(seen, _)| *seen == message) {
            Some((_, count)) => *count += 1,
            None => counted.push((message, 1)),
        }
    }
    counted.into_iter().map(|(message, count)| format!("{message} (x{count})")).collect()
}

/// Runs a probe: a refused attempt is how a probe finds a capability missing or broken, so the
/// GL API errors raised while it runs are its evidence, returned with its result and no longer
/// counted against the case (`gl_api_errors`); the records stay in the diagnostics, marked.
pub fn probing<T>(probe: impl FnOnce() -> T) -> (T, Vec<String>) {
    let start = CAPTURED.lock().unwrap_or_else(|e| e.into_inner()).len();
    let result = probe();
    let mut captured = CAPTURED.lock().unwrap_or_else(|e| e.into_inner());
    let start = start.min(captured.len());
    let raised = gl_api_errors(&captured[start..]);
    for record in captured[start..].iter_mut().filter(|r| r.contains(API_ERROR)) {
        *record = record.replacen(API_ERROR, PROBED_API_ERROR, 1);
    }
    (result, raised)
}

/// How wgpu-hal relays an error of the Vulkan validation layer: at error level, the message
/// type, then "[MESSAGE-ID (0xNUMBER)]" and the message on the next line.
const VALIDATION_ERROR: &str = "ERROR wgpu_hal::vulkan::instance: VALIDATION [";

/// The validation layer's errors among `records`: each distinct message once, as
/// "MESSAGE-ID: message" (its first line, without the objects' handles and the message number
/// the layer puts first), with its count, in order of first appearance.
pub fn validation_errors(records: &[String]) -> Vec<(String, usize)> {
    let mut counted: Vec<(String, usize)> = Vec::new();
    for record in records {
        let Some(rest) = record.strip_prefix(VALIDATION_ERROR) else {
            continue;
        };
        let (id, message) = rest.split_once(']').unwrap_or((rest, ""));
        let id = id.split_once(" (0x").map_or(id, |(name, _)| name).trim();
        let message = message.trim().lines().next().unwrap_or_default().trim();
        // "Validation Error: [ ID ] Object 0: handle = 0x…; | MessageID = 0x… | what it says"
        let said = message.split_once("| MessageID = ").and_then(|(_, rest)| rest.split_once(" | "));
        let message = said.map_or(message, |(_, said)| said.trim());
        let text = format!("{id}: {message}");
        match counted.iter_mut().find(|(seen, _)| *seen == text) {
            Some((_, count)) => *count += 1,
            None => counted.push((text, 1)),
        }
    }
    counted
}

/// Whether a record captured and not yet taken contains `text` (what wgpu warned while an
/// instance was made, say).
pub fn logged(text: &str) -> bool {
    CAPTURED.lock().unwrap_or_else(|e| e.into_inner()).iter().any(|record| record.contains(text))
}

/// A probe's finding with the GL errors it met appended, as evidence.
pub fn with_raised(problem: String, raised: &[String]) -> String {
    match raised.is_empty() {
        true => problem,
        false => format!("{problem} (GL errors: {})", raised.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The records are one process-wide list: tests that take them run one at a time.
    static SERIAL: Mutex<()> = Mutex::new(());

    #[test]
    fn records_are_kept_until_taken() {
        let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
        // The test binary has no other logger; a second install fails cleanly.
        let _ = capture(false);
        log::warn!(target: "wgpu_hal::gles::egl", "DRI2: failed to load driver");
        log::info!("not kept: below warnings");
        let taken = take();
        assert!(taken.iter().any(|l| l == "WARN wgpu_hal::gles::egl: DRI2: failed to load driver"), "{taken:?}");
        assert!(!taken.iter().any(|l| l.contains("not kept")));
        assert!(take().iter().all(|l| !l.contains("DRI2")));
    }

    #[test]
    fn a_probe_claims_the_gl_errors_it_met() {
        let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
        let _ = capture(false);
        let record = |id: u32| log::error!(target: "wgpu_hal::gles", "GLES: [API/Error] ID {id} : GL_INVALID_OPERATION in glDrawArraysIndirect");
        record(1);
        let ((), raised) = probing(|| record(2));
        assert_eq!(raised, ["GL_INVALID_OPERATION in glDrawArraysIndirect (x1)"]);
        let taken = take();
        assert_eq!(gl_api_errors(&taken), ["GL_INVALID_OPERATION in glDrawArraysIndirect (x1)"], "{taken:?}");
        assert!(taken.iter().any(|r| r.contains(PROBED_API_ERROR)));
    }

    #[test]
    fn validation_errors_are_counted_by_message_id_and_first_line() {
        let records = [
            "ERROR wgpu_hal::vulkan::instance: VALIDATION [UNASSIGNED-CoreValidation-Shader-InconsistentSpirv (0x6bbb14)]\n\tValidation Error: [ UNASSIGNED-CoreValidation-Shader-InconsistentSpirv ] Object 0: handle = 0x56490bc1c5b0, type = VK_OBJECT_TYPE_DEVICE; | MessageID = 0x6bbb14 | SPIR-V module not valid: Invalid source language operand: 10",
            "WARN wgpu_hal::vulkan::instance: PERFORMANCE [UNASSIGNED-CoreValidation-Shader-OutputNotConsumed (0x609a13b)]\n\tnot consumed",
            "ERROR wgpu_hal::vulkan::instance: VALIDATION [UNASSIGNED-CoreValidation-Shader-InconsistentSpirv (0x6bbb14)]\n\tValidation Error: [ UNASSIGNED-CoreValidation-Shader-InconsistentSpirv ] Object 0: handle = 0x77aa, type = VK_OBJECT_TYPE_DEVICE; | MessageID = 0x6bbb14 | SPIR-V module not valid: Invalid source language operand: 10",
            "ERROR wgpu_hal::vulkan::instance: VALIDATION [VUID-vkCmdDraw-None-02699 (0x1)]\n\tdescriptor set 0 is invalid",
            "ERROR wgpu_hal::gles: GLES: [API/Error] ID 12 : GL_INVALID_OPERATION in glDrawArraysIndirect",
        ]
        .map(String::from);
        assert_eq!(
            validation_errors(&records),
            [
                (
                    "UNASSIGNED-CoreValidation-Shader-InconsistentSpirv: SPIR-V module not valid: Invalid source language operand: 10".to_owned(),
                    2
                ),
                ("VUID-vkCmdDraw-None-02699: descriptor set 0 is invalid".to_owned(), 1),
            ]
        );
    }

    #[test]
    fn gl_api_errors_are_counted_by_message() {
        let records = [
            "ERROR wgpu_hal::gles: GLES: [API/Error] ID 12 : GL_INVALID_OPERATION in glDrawArraysIndirect",
            "ERROR wgpu_hal::gles: GLES: [ShaderCompiler/Error] ID 1 : 0:250(2): error: initializer of type int",
            "ERROR wgpu_hal::gles: GLES: [API/Error] ID 12 : GL_INVALID_OPERATION in glDrawArraysIndirect",
            "ERROR wgpu_hal::gles: GLES: [API/Error] ID 3 : GL_INVALID_ENUM in glTexStorage2DMultisample",
        ]
        .map(String::from);
        assert_eq!(
            gl_api_errors(&records),
            ["GL_INVALID_OPERATION in glDrawArraysIndirect (x2)", "GL_INVALID_ENUM in glTexStorage2DMultisample (x1)"]
        );
    }
}
