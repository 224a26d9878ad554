//! Numbers, counts and times as pages and tables print them for a person: six significant digits
//! (not the 17 that round-trip an f64), whole numbers without a fraction, "1 run" but "2 runs",
//! UTC dates.

/// `value` to six significant digits, trailing zeros dropped; scientific outside 1e-4..1e7.
pub fn number(value: f64) -> String {
    if !value.is_finite() {
        return format!("{value}");
    }
    if value == value.trunc() && value.abs() < 1e15 {
        return format!("{value:.0}");
    }
    let magnitude = value.abs();
    if !(1e-4..1e7).contains(&magnitude) {
        return format!("{value:.5e}").replace("e", "×10^");
    }
    let decimals = (5 - magnitude.log10().floor() as i32).max(0) as usize;
    let text = format!("{value:.decimals$}");
    if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.').to_owned() } else { text }
}

/// `count` and the noun that goes with it: `one` for 1, `many` otherwise ("0 fixes").
pub fn counted(count: usize, one: &str, many: &str) -> String {
    format!("{count} {}", if count == 1 { one } else { many })
}

/// A Unix time as `YYYY-MM-DD HH:MM UTC` (the civil calendar from days since 1970, after
/// Howard Hinnant's `civil_from_days`).
pub fn utc_time(unix: i64) -> String {
    let (days, seconds) = (unix.div_euclid(86_400), unix.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era = (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_index = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_index + 2) / 5 + 1;
    let month = if month_index < 10 { month_index + 3 } else { month_index - 9 };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02} UTC", seconds / 3600, seconds % 3600 / 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_print_six_significant_digits() {
        assert_eq!(number(1.3805079999999998), "1.38051");
        assert_eq!(number(0.1 + 0.2), "0.3");
        assert_eq!(number(42.0), "42");
        assert_eq!(number(-0.000123456789), "-0.000123457");
        assert_eq!(number(123456.789), "123457");
        assert_eq!(number(2.5e-9), "2.50000×10^-9");
        assert_eq!(number(f64::INFINITY), "inf");
        // Whole numbers print whole below 1e15, in the scientific form from there.
        assert_eq!(number(999_999_999_999_999.0), "999999999999999");
        assert_eq!(number(1e15), "1.00000×10^15");
    }

    #[test]
    fn counts_take_the_singular_only_for_one() {
        assert_eq!(counted(1, "regression", "regressions"), "1 regression");
        assert_eq!(counted(0, "fix", "fixes"), "0 fixes");
        assert_eq!(counted(2, "run", "runs"), "2 runs");
    }

    #[test]
    fn unix_times_are_civil_utc_dates() {
        assert_eq!(utc_time(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc_time(951_782_400), "2000-02-29 00:00 UTC");
        assert_eq!(utc_time(1_796_330_520), "2026-12-03 20:42 UTC");
        // Century years are leap years only every fourth century; before 1970 too.
        assert_eq!(utc_time(4_107_456_000), "2100-02-28 00:00 UTC");
        assert_eq!(utc_time(4_107_542_400), "2100-03-01 00:00 UTC");
        assert_eq!(utc_time(13_574_563_200), "2400-02-29 00:00 UTC");
        assert_eq!(utc_time(-2_203_891_200), "1900-03-01 00:00 UTC");
        assert_eq!(utc_time(-60), "1969-12-31 23:59 UTC");
    }
}
