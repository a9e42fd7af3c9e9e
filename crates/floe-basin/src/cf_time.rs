//! CF time coordinates: `<unit> since <date>` in the calendars of the CF
//! conventions (§4.4.1), turned into seconds from a start date.
//!
//! Hand-rolled: the crate that implements cftime (`cftime-rs` 0.1.6) is
//! built only as a Python extension (`crate-type = ["cdylib"]`) and cannot
//! be linked from Rust, and chrono knows the Gregorian calendar alone. Day
//! counts use Hinnant's `days_from_civil` for the proleptic Gregorian
//! calendar and plain arithmetic for the others. The mixed
//! Julian/Gregorian `standard` calendar is read as proleptic Gregorian,
//! which agrees with it from 1582-10-15 on; earlier dates are refused.

/// A CF calendar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Calendar {
    /// `standard`, `gregorian` (from 1582-10-15), `proleptic_gregorian`.
    Gregorian,
    /// `julian`.
    Julian,
    /// `noleap`, `365_day`.
    NoLeap,
    /// `all_leap`, `366_day`.
    AllLeap,
    /// `360_day`: twelve months of 30 days.
    Day360,
}

impl Calendar {
    /// The calendar a CF `calendar` attribute names, with whether it is
    /// the mixed `standard`/`gregorian` one.
    pub fn parse(name: &str) -> Option<(Calendar, bool)> {
        Some(match name.trim().to_ascii_lowercase().as_str() {
            "standard" | "gregorian" => (Calendar::Gregorian, true),
            "proleptic_gregorian" => (Calendar::Gregorian, false),
            "julian" => (Calendar::Julian, false),
            "noleap" | "365_day" => (Calendar::NoLeap, false),
            "all_leap" | "366_day" => (Calendar::AllLeap, false),
            "360_day" => (Calendar::Day360, false),
            _ => return None,
        })
    }

    /// Days from 0000-03-01 (an arbitrary fixed origin) to `y-m-d`.
    fn days(self, y: i64, m: i64, d: i64) -> i64 {
        match self {
            Calendar::Gregorian | Calendar::Julian => {
                // Hinnant, "chrono-Compatible Low-Level Date Algorithms".
                let y = if m <= 2 { y - 1 } else { y };
                let mp = (m + 9) % 12;
                let doy = (153 * mp + 2) / 5 + d - 1;
                let era_days = if self == Calendar::Gregorian {
                    let era = y.div_euclid(400);
                    let yoe = y - era * 400;
                    era * 146097 + yoe * 365 + yoe / 4 - yoe / 100
                } else {
                    let era = y.div_euclid(4);
                    let yoe = y - era * 4;
                    era * 1461 + yoe * 365
                };
                era_days + doy
            }
            Calendar::NoLeap | Calendar::AllLeap => {
                const CUM: [i64; 12] = [0, 31, 59, 90, 120, 151, 181, 212, 243, 273, 304, 334];
                let leap = i64::from(self == Calendar::AllLeap && m > 2);
                let per_year = if self == Calendar::AllLeap { 366 } else { 365 };
                y * per_year + CUM[(m - 1) as usize] + leap + d - 1
            }
            Calendar::Day360 => y * 360 + (m - 1) * 30 + d - 1,
        }
    }

    fn month_length(self, y: i64, m: i64) -> i64 {
        const LEN: [i64; 12] = [31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31];
        let leap = match self {
            Calendar::Gregorian => (y % 4 == 0 && y % 100 != 0) || y % 400 == 0,
            Calendar::Julian => y % 4 == 0,
            Calendar::NoLeap => false,
            Calendar::AllLeap => true,
            Calendar::Day360 => return 30,
        };
        LEN[(m - 1) as usize] + i64::from(leap && m == 2)
    }
}

/// A date and time read from text, seconds of the day included.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DateTime {
    y: i64,
    m: i64,
    d: i64,
    seconds_of_day: f64,
}

/// Parses `YYYY-MM-DD`, optionally followed by `T` or a space and
/// `HH:MM[:SS[.fff]]`, optionally a `Z` or `UTC` or `+00:00`.
fn parse_datetime(text: &str) -> Option<DateTime> {
    let text = text.trim();
    let (date, rest) = match text.find(['T', ' ']) {
        Some(k) => (&text[..k], text[k + 1..].trim()),
        None => (text, ""),
    };
    let mut parts = date.splitn(3, '-');
    let y: i64 = parts.next()?.parse().ok()?;
    let m: i64 = parts.next()?.parse().ok()?;
    let d: i64 = parts.next()?.parse().ok()?;
    let mut seconds_of_day = 0.0;
    let clock = rest
        .trim_end_matches("UTC")
        .trim_end_matches('Z')
        .trim_end_matches("+00:00")
        .trim_end_matches("+0000")
        .trim();
    if !clock.is_empty() {
        let mut hms = clock.split(':');
        let h: f64 = hms.next()?.parse().ok()?;
        let mi: f64 = hms.next().unwrap_or("0").parse().ok()?;
        let s: f64 = hms.next().unwrap_or("0").parse().ok()?;
        if hms.next().is_some()
            || !(0.0..24.0).contains(&h)
            || !(0.0..60.0).contains(&mi)
            || !(0.0..61.0).contains(&s)
        {
            return None;
        }
        seconds_of_day = h * 3600.0 + mi * 60.0 + s;
    }
    if !(1..=12).contains(&m) || d < 1 {
        return None;
    }
    Some(DateTime {
        y,
        m,
        d,
        seconds_of_day,
    })
}

/// Seconds of one `unit` (CF/UDUNITS names), or `None` for units of
/// varying length (months, years) and unknown words.
fn unit_seconds(unit: &str) -> Option<f64> {
    Some(match unit.to_ascii_lowercase().as_str() {
        "seconds" | "second" | "secs" | "sec" | "s" => 1.0,
        "minutes" | "minute" | "mins" | "min" => 60.0,
        "hours" | "hour" | "hrs" | "hr" | "h" => 3600.0,
        "days" | "day" | "d" => 86400.0,
        _ => return None,
    })
}

/// Seconds from `start` (`YYYY-MM-DD[ HH:MM[:SS]]`, `T` or a space between) to the
/// origin of `units` (`"<unit> since <date>"`) in `calendar`, and the
/// seconds of one unit: a time value `v` is `offset + v unit` seconds
/// after `start`.
///
/// # Errors
/// A message saying what is wrong with the units, the start date or the
/// calendar.
pub fn offset_and_unit(
    units: &str,
    calendar_name: &str,
    start: &str,
) -> Result<(f64, f64), String> {
    let (calendar, mixed) = Calendar::parse(calendar_name).ok_or_else(|| {
        format!(
            "unknown calendar \"{calendar_name}\" (CF calendars: standard, gregorian, \
             proleptic_gregorian, julian, noleap, 365_day, all_leap, 366_day, 360_day)"
        )
    })?;
    let mut words = units.trim().splitn(3, ' ');
    let (unit, since, origin) = (words.next(), words.next(), words.next());
    let (Some(unit), Some(since), Some(origin)) = (unit, since, origin) else {
        return Err(format!("units \"{units}\" are not `<unit> since <date>`"));
    };
    if !since.eq_ignore_ascii_case("since") {
        return Err(format!("units \"{units}\" are not `<unit> since <date>`"));
    }
    let unit_s = unit_seconds(unit).ok_or_else(|| {
        format!("units \"{units}\": \"{unit}\" is not seconds, minutes, hours or days")
    })?;
    let origin =
        parse_datetime(origin).ok_or_else(|| format!("units \"{units}\": cannot read the date"))?;
    let start_dt = parse_datetime(start).ok_or_else(|| {
        format!("start_time \"{start}\" is not a date like \"2024-03-01 00:00:00\"")
    })?;
    for (what, dt) in [("the units' date", origin), ("start_time", start_dt)] {
        if dt.d > calendar.month_length(dt.y, dt.m) {
            return Err(format!(
                "{what} has day {} of a month of {} days in calendar {calendar_name}",
                dt.d,
                calendar.month_length(dt.y, dt.m)
            ));
        }
        if mixed && (dt.y, dt.m, dt.d) < (1582, 10, 15) {
            return Err(format!(
                "{what} falls before 1582-10-15, where calendar \"{calendar_name}\" is Julian; \
                 floe reads it as proleptic_gregorian from then on only"
            ));
        }
    }
    let seconds =
        |dt: DateTime| calendar.days(dt.y, dt.m, dt.d) as f64 * 86400.0 + dt.seconds_of_day;
    Ok((seconds(origin) - seconds(start_dt), unit_s))
}

/// `text` (`YYYY-MM-DD[ HH:MM[:SS[.fff]]]`, `T` or a space between, an
/// optional `Z`, `UTC` or `+00:00`) as CF writes a reference date,
/// `YYYY-MM-DD HH:MM:SS` (fractional seconds kept), if it is a date of the
/// proleptic Gregorian calendar.
pub fn cf_date(text: &str) -> Option<String> {
    let dt = parse_datetime(text)?;
    if dt.d > Calendar::Gregorian.month_length(dt.y, dt.m) || !(0..=9999).contains(&dt.y) {
        return None;
    }
    // Whole microseconds, within the day.
    let micros = ((dt.seconds_of_day * 1e6).round() as i64).min(86_400_000_000 - 1);
    let whole = micros / 1_000_000;
    let (h, mi, s) = (whole / 3600, whole / 60 % 60, whole % 60);
    let seconds = match micros % 1_000_000 {
        0 => format!("{s:02}"),
        // "05.25", not "5.250000".
        f => format!("{s:02}.{f:06}").trim_end_matches('0').to_string(),
    };
    Some(format!(
        "{:04}-{:02}-{:02} {h:02}:{mi:02}:{seconds}",
        dt.y, dt.m, dt.d
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn era5_hours_since_1900_match_pythons_datetime() {
        // (datetime(2024,3,1) - datetime(1900,1,1)) / 1 h = 1088400 (Python).
        let (offset, unit) = offset_and_unit(
            "hours since 1900-01-01 00:00:00.0",
            "gregorian",
            "2024-03-01 00:00:00",
        )
        .unwrap();
        assert_eq!(offset + 1_088_400.0 * unit, 0.0);
        // 2024-03-01T06:30 is 1709274600 s after the Unix epoch (Python).
        let (offset, unit) = offset_and_unit(
            "seconds since 1970-01-01",
            "standard",
            "2024-03-01T06:30:00Z",
        )
        .unwrap();
        assert_eq!(offset + 1_709_274_600.0 * unit, 0.0);
    }

    #[test]
    fn model_calendars_count_their_own_days() {
        // A year is 365, 366 or 360 days whatever the year.
        for (cal, len) in [("noleap", 365.0), ("all_leap", 366.0), ("360_day", 360.0)] {
            let (o, u) = offset_and_unit("days since 2023-03-01", cal, "2024-03-01").unwrap();
            assert_eq!(o / u, -len, "{cal}");
        }
        // The Julian calendar has 2000-02-29... and 1900-02-29.
        let (o, u) = offset_and_unit("days since 1900-02-28", "julian", "1900-03-01").unwrap();
        assert_eq!(o / u, -2.0);
        let (o, u) =
            offset_and_unit("days since 1900-02-28", "proleptic_gregorian", "1900-03-01").unwrap();
        assert_eq!(o / u, -1.0);
        // 360_day has a 30 February.
        let (o, u) = offset_and_unit("days since 2000-02-30", "360_day", "2000-03-01").unwrap();
        assert_eq!(o / u, -1.0);
    }

    #[test]
    fn dates_are_written_as_cf_reference_dates() {
        for (text, cf) in [
            ("2024-03-01 00:00:00", Some("2024-03-01 00:00:00")),
            ("2024-3-1T06:30Z", Some("2024-03-01 06:30:00")),
            ("2024-02-29 23:59:59.25 UTC", Some("2024-02-29 23:59:59.25")),
            ("2024-02-29 00:00:05.5", Some("2024-02-29 00:00:05.5")),
            ("1500-01-01", Some("1500-01-01 00:00:00")),
            ("2023-02-29", None),
            ("2024-03-01 24:00:00", None),
            ("yesterday", None),
        ] {
            assert_eq!(cf_date(text).as_deref(), cf, "{text}");
        }
    }

    #[test]
    fn bad_units_dates_and_calendars_say_what_is_wrong() {
        for (units, cal, start, want) in [
            (
                "months since 2000-01-01",
                "standard",
                "2000-01-01",
                "not seconds",
            ),
            ("hours after 2000-01-01", "standard", "2000-01-01", "since"),
            (
                "hours since 2000-01-01",
                "mayan",
                "2000-01-01",
                "unknown calendar",
            ),
            (
                "hours since 2000-01-01",
                "standard",
                "1st of May",
                "start_time",
            ),
            ("hours since 2001-02-29", "noleap", "2000-01-01", "day 29"),
            ("hours since 1500-01-01", "standard", "2000-01-01", "1582"),
        ] {
            let e = offset_and_unit(units, cal, start).unwrap_err();
            assert!(e.contains(want), "{units} {cal}: {e}");
        }
    }
}
