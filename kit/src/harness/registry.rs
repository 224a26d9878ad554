//! Registering cases: each area of a suite lists its case files once, with the cases each file
//! declares, in run order; that list is both the files' module declarations and the area's
//! registry. A suite's registry is its areas' lists joined ([`join`]); its tests take one test
//! per registered case from it.

use std::sync::OnceLock;

use super::case::Case;

/// Declares an area's case files and registers their cases, in run order:
///
/// ```ignore
/// fragkit::cases! {
///     raster_subpixel_precision: CASE;
///     msaa_sample_positions: CASE_1X, CASE_2X;
/// }
/// ```
/// declares `pub mod raster_subpixel_precision;` and `pub mod msaa_sample_positions;` and the
/// area's registry `pub const CASES: &[&Case]`, `[&raster_subpixel_precision::CASE,
/// &msaa_sample_positions::CASE_1X, &msaa_sample_positions::CASE_2X]`.
#[macro_export]
macro_rules! cases {
    ($($file:ident: $($case:ident),+;)*) => {
        $(pub mod $file;)*

        /// This area's cases, in run order.
        pub const CASES: &[&$crate::harness::Case] = &[$($(&$file::$case),+),*];
    };
}

/// A suite's registry, its areas' cases in order, joined once into one list for the process.
pub fn join(registry: &'static OnceLock<Vec<Case>>, areas: &[&[&Case]]) -> &'static [Case] {
    registry.get_or_init(|| areas.iter().flat_map(|area| area.iter().map(|&&case| case)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The areas' cases in their order, joined once: a later call gets the first list.
    #[test]
    fn a_suites_registry_is_its_areas_cases_in_order_joined_once() {
        static REGISTRY: OnceLock<Vec<Case>> = OnceLock::new();
        let (one, two, three) = (Case::passing("a.one"), Case::passing("a.two"), Case::passing("b.one"));
        let names = |cases: &[Case]| cases.iter().map(|case| case.name).collect::<Vec<_>>();
        assert_eq!(names(join(&REGISTRY, &[&[&one, &two], &[], &[&three]])), ["a.one", "a.two", "b.one"]);
        assert_eq!(names(join(&REGISTRY, &[&[&three]])), ["a.one", "a.two", "b.one"]);
    }
}
