//! What each fetch variant of `shaders/texarray/fetch.wgsl` may return for element k, from its
//! definition and what the specifications allow, never from a GPU: the variant's f32 arithmetic
//! carried as intervals (WGSL: `+ − ×` and conversions correctly rounded to either neighbour,
//! `/` within 2.5 ULP, `floor`/`fract` exact), then the sampler's nearest texel with texel
//! coordinates held to only 4 fractional bits (Vulkan's minimum `subTexelPrecisionBits`, which
//! GL and WebGPU do not exceed) and repeat addressing. The result is the set of elements the
//! variant may fetch: `{k}` where the formats make it exact, a few neighbours where they do not.
//! A GPU result outside that set is a wrong address, whatever the adapter's own precision.

use super::FetchVariant;

/// A closed interval of reals holding every value an f32 computation may produce.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Interval {
    lo: f64,
    hi: f64,
}

/// The spacing of f32 values at magnitude `x` (normal range).
fn ulp(x: f64) -> f64 {
    let magnitude = x.abs().max(f64::from(f32::MIN_POSITIVE));
    2f64.powi(magnitude.log2().floor() as i32 - 23)
}

impl Interval {
    fn exact(value: f64) -> Self {
        Self { lo: value, hi: value }
    }

    /// Widened by `ulps` units in the last place at each end; rounding never changes a sign, so
    /// a zero stays zero.
    fn rounded(lo: f64, hi: f64, ulps: f64) -> Self {
        let widen = |x: f64, direction: f64| if x == 0.0 { 0.0 } else { x + direction * ulps * ulp(x) };
        let (wide_lo, wide_hi) = (widen(lo, -1.0), widen(hi, 1.0));
        Self {
            lo: if lo >= 0.0 { wide_lo.max(0.0) } else { wide_lo },
            hi: if hi <= 0.0 { wide_hi.min(0.0) } else { wide_hi },
        }
    }

    /// `f32(k)`: exact below 2^24, else either neighbouring f32.
    fn from_index(k: u32) -> Self {
        let k = f64::from(k);
        if k <= f64::from(1u32 << 24) { Self::exact(k) } else { Self::rounded(k, k, 1.0) }
    }

    fn add(self, other: Self) -> Self {
        Self::rounded(self.lo + other.lo, self.hi + other.hi, 0.5)
    }

    fn sub(self, other: Self) -> Self {
        Self::rounded(self.lo - other.hi, self.hi - other.lo, 0.5)
    }

    fn mul(self, other: Self) -> Self {
        let products = [self.lo * other.lo, self.lo * other.hi, self.hi * other.lo, self.hi * other.hi];
        let (lo, hi) = bounds(&products);
        Self::rounded(lo, hi, 0.5)
    }

    /// By a positive divisor, within WGSL's 2.5 ULP.
    fn div(self, divisor: Self) -> Self {
        let quotients = [self.lo / divisor.lo, self.lo / divisor.hi, self.hi / divisor.lo, self.hi / divisor.hi];
        let (lo, hi) = bounds(&quotients);
        Self::rounded(lo, hi, 2.5)
    }

    /// Every whole number `floor` may give.
    fn floors(self) -> std::ops::RangeInclusive<i64> {
        self.lo.floor() as i64..=self.hi.floor() as i64
    }

    /// `fract`: exact for the non-negative values here; a range crossing a whole number may give
    /// anything in [0, 1).
    fn fract(self) -> Self {
        if self.lo.floor() == self.hi.floor() {
            Self { lo: self.lo - self.lo.floor(), hi: self.hi - self.hi.floor() }
        } else {
            Self { lo: 0.0, hi: 1.0 }
        }
    }
}

fn bounds(values: &[f64]) -> (f64, f64) {
    values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)))
}

/// Fractional bits of a texel coordinate every implementation keeps (Vulkan's minimum).
const SUB_TEXEL_BITS: i32 = 4;

/// The texels nearest sampling with repeat addressing may pick along an axis of `size` texels
/// for a normalised coordinate in `coordinate`: the texel coordinate `coordinate × size` (a
/// correctly rounded product), off by up to one sub-texel step either way, floored and wrapped.
fn nearest_texels(coordinate: Interval, size: u32) -> Vec<u32> {
    let texel = coordinate.mul(Interval::exact(f64::from(size)));
    let step = 2f64.powi(-SUB_TEXEL_BITS);
    let (first, last) = ((texel.lo - step).floor() as i64, (texel.hi + step).floor() as i64);
    // A span of the whole axis or more holds every texel.
    if (first..=last).count() >= size as usize {
        return (0..size).collect();
    }
    let mut texels: Vec<u32> = (first..=last).map(|t| t.rem_euclid(i64::from(size)) as u32).collect();
    texels.sort_unstable();
    texels.dedup();
    texels
}

/// The elements of a texel centre (x + ½, y + ½)/(w, h) for x, y in the given intervals.
fn at_centre(x: Interval, y: Interval, (w, h): (f64, f64), size: (u32, u32)) -> Vec<u64> {
    let half = Interval::exact(0.5);
    let u = x.add(half).div(Interval::exact(w));
    let v = y.add(half).div(Interval::exact(h));
    elements(&nearest_texels(u, size.0), &nearest_texels(v, size.1), size.0)
}

fn elements(columns: &[u32], rows: &[u32], width: u32) -> Vec<u64> {
    rows.iter()
        .flat_map(|&row| columns.iter().map(move |&column| u64::from(row) * u64::from(width) + u64::from(column)))
        .collect()
}

/// Every element `variant` may fetch for index `k` of a `size` texture, sorted.
pub fn possible_elements(variant: FetchVariant, k: u32, size: (u32, u32)) -> Vec<u64> {
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    let (wi, hi) = (Interval::exact(w), Interval::exact(h));
    let kf = Interval::from_index(k);
    let mut found: Vec<u64> = match variant {
        FetchVariant::Integer => vec![u64::from(k)],
        FetchVariant::Divide => {
            // y = floor(k / w), x = k − y·w, sampled at (x, y)'s centre.
            kf.div(wi)
                .floors()
                .flat_map(|y| {
                    let y = Interval::exact(y as f64);
                    at_centre(kf.sub(y.mul(wi)), y, (w, h), size)
                })
                .collect()
        }
        FetchVariant::Reciprocal => {
            // t = k·(1/w); x = floor(fract(t)·w + ½), y = floor(t).
            let t = kf.mul(Interval::exact(1.0).div(wi));
            let x = t.fract().mul(wi).add(Interval::exact(0.5));
            x.floors()
                .flat_map(|x| t.floors().map(move |y| (x, y)))
                .flat_map(|(x, y)| at_centre(Interval::exact(x as f64), Interval::exact(y as f64), (w, h), size))
                .collect()
        }
        FetchVariant::SingleMultiply => {
            // uv = (1/w, 1/(w·h))·(k + ½), wrapped by the sampler.
            let centre = kf.add(Interval::exact(0.5));
            let u = Interval::exact(1.0).div(wi).mul(centre);
            let v = Interval::exact(1.0).div(wi.mul(hi)).mul(centre);
            elements(&nearest_texels(u, size.0), &nearest_texels(v, size.1), size.0)
        }
    };
    found.sort_unstable();
    found.dedup();
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The interval arithmetic's pieces by their definitions: widening by ULPs without crossing
    /// zero, `f32(k)` exact up to 2^24, `fract` within one whole number, and nearest texels one
    /// sub-texel step either side of the texel coordinate.
    #[test]
    fn interval_pieces_follow_their_definitions() {
        let half = Interval::rounded(1.0, 2.0, 0.5);
        assert_eq!(half, Interval { lo: 1.0 - 0.5 * 2f64.powi(-23), hi: 2.0 + 0.5 * 2f64.powi(-22) });
        assert_eq!(Interval::rounded(0.0, 0.0, 3.0), Interval::exact(0.0));
        // The smallest values widen towards zero but never past it.
        let tiny = 2f64.powi(-150);
        assert_eq!(Interval::rounded(tiny, tiny, 1.0).lo, 0.0);
        assert_eq!(Interval::rounded(-tiny, -tiny, 1.0).hi, 0.0);
        assert_eq!(
            Interval::rounded(-3.0, -1.0, 1.0),
            Interval { lo: -3.0 - 2f64.powi(-22), hi: -1.0 + 2f64.powi(-23) }
        );
        assert_eq!(Interval::from_index(1 << 24), Interval::exact(16_777_216.0));
        let past = f64::from((1u32 << 24) + 1);
        assert_eq!(Interval::from_index((1 << 24) + 1), Interval { lo: past - 2.0, hi: past + 2.0 });
        assert_eq!(Interval { lo: 1.25, hi: 1.5 }.fract(), Interval { lo: 0.25, hi: 0.5 });
        assert_eq!(Interval { lo: 1.75, hi: 2.25 }.fract(), Interval { lo: 0.0, hi: 1.0 });
        // 0.5 of 8 texels is texel coordinate 4: a 1/16 step either side reaches texel 3.
        assert_eq!(nearest_texels(Interval::exact(0.5), 8), [3, 4]);
        assert_eq!(nearest_texels(Interval::exact(0.53), 8), [4]);
        // Repeat addressing wraps texel −1 to 7; a range over every texel is every texel.
        assert_eq!(nearest_texels(Interval::exact(0.0), 8), [0, 7]);
        assert_eq!(nearest_texels(Interval { lo: 0.1, hi: 0.95 }, 8), (0..8).collect::<Vec<_>>());
    }

    #[test]
    fn the_integer_fetch_is_exact_and_the_float_ones_where_the_formats_allow() {
        let size = (4096, 4097);
        for k in [0, 1, 4095, 4096, 1 << 20, (1 << 24) + 7] {
            assert_eq!(possible_elements(FetchVariant::Integer, k, size), [u64::from(k)]);
        }
        // Small indices away from a row's ends: one element for the float variants too.
        for variant in [FetchVariant::Divide, FetchVariant::Reciprocal] {
            for k in [0, 1, 1000] {
                assert_eq!(possible_elements(variant, k, size), [u64::from(k)], "{variant:?} {k}");
            }
        }
        // A row's first element: k / w may come out below the whole number (2.5 ULP), and the
        // divide variant then fetches x = w of the row before, which wraps to its first element.
        assert_eq!(possible_elements(FetchVariant::Divide, 4096, size), [0, 4096]);
        // One multiply: the row coordinate's margin is half a texel's 1/4096, below 4 sub-texel
        // bits, so a row's first element may come from the row above (SwiftShader fetches 0 for
        // 4096).
        assert!(possible_elements(FetchVariant::SingleMultiply, 4096, size).contains(&0));
        assert!(possible_elements(FetchVariant::SingleMultiply, 4096, size).contains(&4096));
        // Past 2^24, f32(k) is not k: neighbours are allowed, far elements are not.
        let past = (1 << 24) + 1;
        let allowed = possible_elements(FetchVariant::Divide, past, size);
        assert!(allowed.contains(&(1 << 24)) && allowed.iter().all(|&e| e.abs_diff(u64::from(past)) <= 4096 + 2));
    }
}
