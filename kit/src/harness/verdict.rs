//! A case's verdict as it compares: every problem it finds, gathered in order, and at the end
//! one outcome — a pass when none was found, else a failure naming them all ("; " between them,
//! the separator the expectations file splits a failure at).

use super::case::Outcome;

/// The problems a case has found so far.
#[must_use = "a verdict decides nothing until it becomes the case's outcome (`Verdict::outcome`)"]
#[derive(Debug, Default)]
pub struct Verdict {
    problems: Vec<String>,
}

impl Verdict {
    pub fn new() -> Self {
        Self::default()
    }

    /// Records a problem.
    pub fn fail(&mut self, problem: impl Into<String>) {
        self.problems.push(problem.into());
    }

    /// Records the problem `problem` describes unless `holds`.
    pub fn expect(&mut self, holds: bool, problem: impl FnOnce() -> String) {
        if !holds {
            self.problems.push(problem());
        }
    }

    /// Records every problem of `problems` (a check that returns the ones it found).
    pub fn extend(&mut self, problems: impl IntoIterator<Item = String>) {
        self.problems.extend(problems);
    }

    /// Whether no problem was found so far.
    pub fn is_clean(&self) -> bool {
        self.problems.is_empty()
    }

    /// The problems found so far.
    pub fn problems(&self) -> &[String] {
        &self.problems
    }

    /// The case's outcome: a pass when nothing was found, else a failure naming every problem.
    pub fn outcome(self) -> Outcome {
        if self.problems.is_empty() { Outcome::Pass } else { Outcome::Fail(self.problems.join("; ")) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_problem_passes_and_every_problem_is_named_in_order() {
        assert_eq!(Verdict::new().outcome(), Outcome::Pass);
        let mut verdict = Verdict::new();
        verdict.expect(true, || "not this".into());
        assert!(verdict.is_clean() && verdict.problems().is_empty());
        verdict.fail("first");
        assert!(!verdict.is_clean());
        verdict.expect(false, || "second".into());
        verdict.extend(["third".to_owned()]);
        assert_eq!(verdict.problems().len(), 3);
        assert_eq!(verdict.outcome(), Outcome::Fail("first; second; third".into()));
    }
}
