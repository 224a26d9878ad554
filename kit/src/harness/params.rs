//! Named case parameters with typed defaults, overridable with `--set key=value`.

use std::collections::BTreeMap;

use anyhow::{Context, Result, bail};
use fragkit_report::param_value::ParamValue;
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    /// A non-negative integer.
    Count,
    /// An integer in `min..=max`.
    CountIn(u64, u64),
    /// A comma-separated list of non-negative integers: `1,2,4,8`.
    Counts,
    /// A comma-separated list of sizes: `1x1,7x5,64x64`.
    Sizes,
    /// Sizes whose sides are all at least this.
    SizesFrom(u32),
    /// One size: `64x48` (recorded as a list of one, as `Sizes` records it).
    Size,
    /// One size whose sides are both at least this.
    SizeFrom(u32),
}

/// A parameter a case declares.
#[derive(Clone, Copy, Debug)]
pub struct ParamSpec {
    pub name: &'static str,
    pub kind: ParamKind,
    pub default: &'static str,
    pub help: &'static str,
}

fn parse_count(text: &str) -> Result<u64> {
    text.trim().parse::<u64>().with_context(|| format!("{text:?} is not a non-negative integer"))
}

fn parse_size(text: &str) -> Result<(u32, u32)> {
    let (w, h) = text.trim().split_once('x').with_context(|| format!("{text:?} is not a size like 64x32"))?;
    let parse = |v: &str| v.trim().parse::<u32>().with_context(|| format!("{v:?} in size {text:?} is not an integer"));
    let size = (parse(w)?, parse(h)?);
    if size.0 == 0 || size.1 == 0 {
        bail!("size {text:?} is empty; both sides must be at least 1");
    }
    Ok(size)
}

impl ParamKind {
    pub fn parse(self, text: &str) -> Result<ParamValue> {
        Ok(match self {
            ParamKind::Count => ParamValue::Count(parse_count(text)?),
            ParamKind::CountIn(min, max) => {
                let value = parse_count(text)?;
                if !(min..=max).contains(&value) {
                    bail!("{value} is outside the allowed range {min}..={max}");
                }
                ParamValue::Count(value)
            }
            ParamKind::Counts => ParamValue::Counts(text.split(',').map(parse_count).collect::<Result<_>>()?),
            ParamKind::Sizes => ParamValue::Sizes(text.split(',').map(parse_size).collect::<Result<_>>()?),
            ParamKind::SizesFrom(min) => {
                let sizes: Vec<(u32, u32)> = text.split(',').map(parse_size).collect::<Result<_>>()?;
                if let Some((w, h)) = sizes.iter().find(|(w, h)| *w < min || *h < min) {
                    bail!("size {w}x{h} is too small: both sides must be at least {min}");
                }
                ParamValue::Sizes(sizes)
            }
            ParamKind::Size => ParamKind::SizeFrom(1).parse(text)?,
            ParamKind::SizeFrom(min) => {
                if text.contains(',') {
                    bail!("{text:?} is a list; this parameter takes one size, like 64x48");
                }
                ParamKind::SizesFrom(min).parse(text)?
            }
        })
    }

    /// Whether values of this kind are sizes (a list, or one).
    pub fn is_size(self) -> bool {
        matches!(self, Self::Sizes | Self::SizesFrom(_) | Self::Size | Self::SizeFrom(_))
    }
}

/// One case's resolved parameter values.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Params(BTreeMap<&'static str, ParamValue>);

impl Params {
    /// The values by name, as a report records them.
    pub fn to_map(&self) -> BTreeMap<String, ParamValue> {
        self.0.iter().map(|(k, v)| ((*k).to_owned(), v.clone())).collect()
    }

    /// Defaults of `specs`, with `overrides` (key → text) applied where a spec has that key.
    pub fn resolve(case: &str, specs: &[ParamSpec], overrides: &BTreeMap<String, String>) -> Result<Self> {
        let mut values = BTreeMap::new();
        for spec in specs {
            let (text, source) = match overrides.get(spec.name) {
                Some(text) => (text.as_str(), "--set"),
                None => (spec.default, "the default"),
            };
            let value = spec
                .kind
                .parse(text)
                .with_context(|| format!("parameter {:?} of {case} (from {source}): {}", spec.name, spec.help))?;
            values.insert(spec.name, value);
        }
        Ok(Self(values))
    }

    fn get(&self, name: &str) -> Result<&ParamValue> {
        self.0.get(name).with_context(|| format!("case declares no parameter {name:?}"))
    }

    pub fn count(&self, name: &str) -> Result<u64> {
        match self.get(name)? {
            ParamValue::Count(v) => Ok(*v),
            other => bail!("parameter {name:?} is {other:?}, not a count"),
        }
    }

    pub fn counts(&self, name: &str) -> Result<Vec<u64>> {
        match self.get(name)? {
            ParamValue::Counts(v) => Ok(v.clone()),
            other => bail!("parameter {name:?} is {other:?}, not a list of counts"),
        }
    }

    /// A count that a 32-bit quantity takes (a seed, a frame count): a value past `u32::MAX` is
    /// an error, never truncated.
    pub fn count_u32(&self, name: &str) -> Result<u32> {
        let value = self.count(name)?;
        u32::try_from(value).with_context(|| format!("parameter {name:?} = {value} does not fit in 32 bits"))
    }

    /// A parameter of one size (`ParamKind::Size`).
    pub fn size(&self, name: &str) -> Result<(u32, u32)> {
        match self.sizes(name)?.as_slice() {
            [size] => Ok(*size),
            sizes => bail!("parameter {name:?} holds {} sizes where one is taken", sizes.len()),
        }
    }

    pub fn sizes(&self, name: &str) -> Result<Vec<(u32, u32)>> {
        match self.get(name)? {
            ParamValue::Sizes(v) => Ok(v.clone()),
            other => bail!("parameter {name:?} is {other:?}, not a list of sizes"),
        }
    }
}

/// The range a parameter may take in a sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepRange {
    /// An integer in `min..=max`, drawn log-uniformly (as many small values as large ones).
    Count(u64, u64),
    /// One size whose width and height are each drawn log-uniformly between the corners.
    Size { min: (u32, u32), max: (u32, u32) },
}

/// A parameter a case lets sweeps vary, and its range; the others keep their defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sweep {
    pub param: &'static str,
    pub range: SweepRange,
}

/// Parses `--set key=value` arguments.
pub fn parse_overrides(sets: &[String]) -> Result<BTreeMap<String, String>> {
    let mut overrides = BTreeMap::new();
    for set in sets {
        let (key, value) = set.split_once('=').with_context(|| format!("--set {set:?}: expected key=value"))?;
        let key = key.trim().to_owned();
        if let Some(earlier) = overrides.insert(key.clone(), value.trim().to_owned()) {
            anyhow::bail!("--set {key} is given twice ({earlier:?} and {:?}); give each parameter once", value.trim());
        }
    }
    Ok(overrides)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECS: &[ParamSpec] = &[
        ParamSpec { name: "size", kind: ParamKind::SizeFrom(2), default: "8x4", help: "" },
        ParamSpec { name: "seed", kind: ParamKind::Count, default: "1", help: "" },
    ];

    fn resolved(sets: &[(&str, &str)]) -> Result<Params> {
        let overrides = sets.iter().map(|(k, v)| ((*k).to_owned(), (*v).to_owned())).collect();
        Params::resolve("kit.example", SPECS, &overrides)
    }

    #[test]
    fn a_single_size_is_one_size_recorded_as_a_list_of_one() {
        let params = resolved(&[("size", "7x5")]).unwrap();
        assert_eq!(params.size("size").unwrap(), (7, 5));
        assert_eq!(params.to_map()["size"], ParamValue::Sizes(vec![(7, 5)]));
        for bad in ["7x5,9x9", "1x5", "7x"] {
            assert!(resolved(&[("size", bad)]).is_err(), "size {bad} accepted");
        }
    }

    #[test]
    fn a_32_bit_count_past_u32_is_refused_not_truncated() {
        assert_eq!(resolved(&[("seed", "4294967295")]).unwrap().count_u32("seed").unwrap(), u32::MAX);
        let error = resolved(&[("seed", "4294967296")]).unwrap().count_u32("seed").unwrap_err();
        assert!(format!("{error:#}").contains("does not fit in 32 bits"), "{error:#}");
    }

    #[test]
    fn each_kind_reads_its_values_up_to_its_bounds_and_no_further() {
        use ParamValue::*;
        let parse = |kind: ParamKind, text: &str| kind.parse(text).ok();
        assert_eq!(parse(ParamKind::Count, " 12 "), Some(Count(12)));
        assert_eq!(parse(ParamKind::Count, "-1"), None);
        assert_eq!(parse(ParamKind::CountIn(2, 5), "2"), Some(Count(2)));
        assert_eq!(parse(ParamKind::CountIn(2, 5), "5"), Some(Count(5)));
        assert_eq!(parse(ParamKind::CountIn(2, 5), "1"), None);
        assert_eq!(parse(ParamKind::CountIn(2, 5), "6"), None);
        assert_eq!(parse(ParamKind::Counts, "1, 4,8"), Some(Counts(vec![1, 4, 8])));
        assert_eq!(parse(ParamKind::Counts, "1,x"), None);
        assert_eq!(parse(ParamKind::Sizes, "1x1, 7x5"), Some(Sizes(vec![(1, 1), (7, 5)])));
        assert_eq!(parse(ParamKind::Sizes, "0x5"), None);
        assert_eq!(parse(ParamKind::Sizes, "5x0"), None);
        assert_eq!(parse(ParamKind::Sizes, "5by5"), None);
        assert_eq!(parse(ParamKind::SizesFrom(4), "4x4,9x4"), Some(Sizes(vec![(4, 4), (9, 4)])));
        assert_eq!(parse(ParamKind::SizesFrom(4), "4x4,3x9"), None);
        assert_eq!(parse(ParamKind::SizesFrom(4), "9x3"), None);
        assert_eq!(parse(ParamKind::Size, "1x1"), Some(Sizes(vec![(1, 1)])));
        assert_eq!(parse(ParamKind::Size, "0x1"), None);
        assert_eq!(parse(ParamKind::Size, "1x1,2x2"), None);
        assert_eq!(parse(ParamKind::SizeFrom(3), "3x3"), Some(Sizes(vec![(3, 3)])));
        assert_eq!(parse(ParamKind::SizeFrom(3), "3x2"), None);
        let sizes = [ParamKind::Sizes, ParamKind::SizesFrom(2), ParamKind::Size, ParamKind::SizeFrom(2)];
        assert!(sizes.iter().all(|k| k.is_size()));
        assert!([ParamKind::Count, ParamKind::CountIn(0, 1), ParamKind::Counts].iter().all(|k| !k.is_size()));
    }

    #[test]
    fn values_are_read_back_by_their_own_kind_only() {
        let specs = [
            ParamSpec { name: "n", kind: ParamKind::Count, default: "3", help: "how many" },
            ParamSpec { name: "list", kind: ParamKind::Counts, default: "1,2", help: "" },
            ParamSpec { name: "sizes", kind: ParamKind::Sizes, default: "2x2,3x3", help: "" },
        ];
        let params = Params::resolve("kit.x", &specs, &BTreeMap::new()).unwrap();
        assert_eq!((params.count("n").unwrap(), params.counts("list").unwrap()), (3, vec![1, 2]));
        assert_eq!(params.sizes("sizes").unwrap(), [(2, 2), (3, 3)]);
        assert!(format!("{:#}", params.size("sizes").unwrap_err()).contains("holds 2 sizes where one is taken"));
        for (name, wrong) in [("n", "counts"), ("list", "count"), ("sizes", "count"), ("n", "sizes")] {
            let read = match wrong {
                "counts" => params.counts(name).map(drop),
                "count" => params.count(name).map(drop),
                _ => params.sizes(name).map(drop),
            };
            assert!(read.is_err(), "{name} read as {wrong}");
        }
        assert!(format!("{:#}", params.count("none").unwrap_err()).contains("declares no parameter \"none\""));
        // An override is named as the source of a bad value, with the parameter's help.
        let bad = Params::resolve("kit.x", &specs, &[("n".to_owned(), "x".to_owned())].into()).unwrap_err();
        assert!(format!("{bad:#}").contains("parameter \"n\" of kit.x (from --set): how many"), "{bad:#}");
        // Overrides of names the case does not declare are not its business.
        let other = Params::resolve("kit.x", &specs, &[("m".to_owned(), "x".to_owned())].into()).unwrap();
        assert_eq!(other.to_map().len(), 3);
    }

    #[test]
    fn set_arguments_are_trimmed_pairs_given_once() {
        let sets = |items: &[&str]| parse_overrides(&items.iter().map(|s| (*s).to_owned()).collect::<Vec<_>>());
        assert_eq!(
            sets(&[" size = 8x8", "seed=3"]).unwrap(),
            BTreeMap::from([("seed".to_owned(), "3".to_owned()), ("size".to_owned(), "8x8".to_owned())])
        );
        assert!(sets(&["size"]).is_err());
        let twice = sets(&["seed=1", "seed =2"]).unwrap_err();
        assert!(format!("{twice:#}").contains("--set seed is given twice (\"1\" and \"2\")"), "{twice:#}");
    }
}
