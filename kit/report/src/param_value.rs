//! A case parameter's value as a report records it.

use serde::{Deserialize, Serialize};

/// A parameter value: a count, a list of counts or a list of sizes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ParamValue {
    Count(u64),
    Counts(Vec<u64>),
    Sizes(Vec<(u32, u32)>),
}

impl ParamValue {
    /// The value as `--set` takes it (`8`, `1,4`, `64x48,7x5`): [`ParamKind::parse`] reads it back.
    pub fn to_text(&self) -> String {
        let join = |items: Vec<String>| items.join(",");
        match self {
            Self::Count(v) => v.to_string(),
            Self::Counts(vs) => join(vs.iter().map(u64::to_string).collect()),
            Self::Sizes(sizes) => join(sizes.iter().map(|(w, h)| format!("{w}x{h}")).collect()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_reads_as_set_takes_it() {
        assert_eq!(ParamValue::Count(8).to_text(), "8");
        assert_eq!(ParamValue::Counts(vec![1, 4]).to_text(), "1,4");
        assert_eq!(ParamValue::Sizes(vec![(64, 48), (7, 5)]).to_text(), "64x48,7x5");
    }
}
