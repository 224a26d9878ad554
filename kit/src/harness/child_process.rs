//! How a child process ended, in words, and the last lines it logged: what a supervisor says
//! about a case list's child, or a matrix about a configuration's.

use std::ffi::OsString;
use std::path::Path;
use std::process::ExitStatus;

fn signal_name(signal: i32) -> &'static str {
    match signal {
        4 => "SIGILL",
        6 => "SIGABRT",
        7 => "SIGBUS",
        8 => "SIGFPE",
        9 => "SIGKILL",
        11 => "SIGSEGV",
        15 => "SIGTERM",
        _ => "signal",
    }
}

/// How a process ended, in words: the signal that killed it, or its exit code.
pub fn ending(status: &ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(signal) = status.signal() {
            return format!("killed by signal {signal} ({})", signal_name(signal));
        }
    }
    match status.code() {
        Some(code) => format!("exit {code}"),
        None => "ended without a code".into(),
    }
}

/// A command line (`words`, after the program name) without the flags in `strip` (each with its
/// value, as `--flag value` or `--flag=value`) and the `switches` (flags without a value): the
/// parent's own command line, less what only the parent writes, for its children.
pub fn arguments_without(
    words: impl IntoIterator<Item = OsString>,
    strip: &[&str],
    switches: &[&str],
) -> Vec<OsString> {
    let mut kept = Vec::new();
    let mut words = words.into_iter();
    while let Some(word) = words.next() {
        let text = word.to_string_lossy();
        if switches.iter().any(|flag| text == *flag) {
            continue;
        }
        if strip.iter().any(|flag| text == *flag) {
            words.next();
        } else if !strip.iter().any(|flag| text.starts_with(&format!("{flag}="))) {
            kept.push(word);
        }
    }
    kept
}

/// The last `lines` lines of the log at `path` (empty when it cannot be read).
pub fn log_tail(path: &Path, lines: usize) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<OsString> {
        text.split_whitespace().map(OsString::from).collect()
    }

    #[test]
    fn children_get_the_command_line_without_what_only_the_parent_writes() {
        let line = words("kit.* --json r.json --set k=1 --db=runs.db --github -v");
        assert_eq!(arguments_without(line, &["--json", "--db"], &["--github"]), words("kit.* --set k=1 -v"));
    }

    #[test]
    fn an_ending_names_the_signal_or_the_exit_code() {
        use std::os::unix::process::ExitStatusExt;
        // A wait status: the signal in the low bits, an exit code in the next byte.
        let cases = [
            (4, "killed by signal 4 (SIGILL)"),
            (6, "killed by signal 6 (SIGABRT)"),
            (7, "killed by signal 7 (SIGBUS)"),
            (8, "killed by signal 8 (SIGFPE)"),
            (9, "killed by signal 9 (SIGKILL)"),
            (11, "killed by signal 11 (SIGSEGV)"),
            (15, "killed by signal 15 (SIGTERM)"),
            (5, "killed by signal 5 (signal)"),
            (3 << 8, "exit 3"),
            (0, "exit 0"),
        ];
        for (raw, words) in cases {
            assert_eq!(ending(&ExitStatus::from_raw(raw)), words);
        }
    }

    #[test]
    fn a_log_tail_is_its_last_lines_or_nothing() {
        let path = std::env::temp_dir().join(format!("fragkit-log-tail-{}.log", std::process::id()));
        std::fs::write(&path, "one\ntwo\nthree\n").unwrap();
        assert_eq!(log_tail(&path, 2), "two\nthree");
        assert_eq!(log_tail(&path, 5), "one\ntwo\nthree");
        assert_eq!(log_tail(&path, 0), "");
        std::fs::remove_file(&path).unwrap();
        assert_eq!(log_tail(&path, 2), "");
    }
}
