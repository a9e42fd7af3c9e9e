//! Time series as CSV: writing spring-slider output, reading measured data.

use std::path::Path;

use floe_friction::fit::FitData;
use floe_friction::spring_slider::Sample;

use crate::CliError;

/// Column header of `series.csv`, with units.
pub const SERIES_HEADER: [&str; 6] = [
    "t_s",
    "load_point_m",
    "slider_m",
    "slip_rate_m_per_s",
    "theta",
    "mu",
];

/// Writes samples to `path` as CSV (full f64 precision).
pub fn write_series(path: &Path, samples: &[Sample]) -> Result<(), CliError> {
    let io = |e: csv::Error| CliError::io(path, e.into());
    let mut w = csv::Writer::from_path(path).map_err(io)?;
    w.write_record(SERIES_HEADER).map_err(io)?;
    for s in samples {
        w.write_record(
            [
                s.t_s,
                s.load_point_m,
                s.slider_m,
                s.slip_rate_m_per_s,
                s.theta,
                s.mu,
            ]
            .map(|x| format!("{x:e}")),
        )
        .map_err(io)?;
    }
    w.flush().map_err(|e| CliError::io(path, e))
}

/// Accepted names of the time column of a measured series.
const TIME_COLUMNS: [&str; 3] = ["t_s", "time_s", "t"];

/// Reads a measured friction series: a CSV with a header naming a time
/// column (`t_s`, `time_s` or `t`, seconds from the start of the protocol)
/// and a `mu` column; other columns are ignored.
pub fn read_fit_data(path: &Path) -> Result<FitData, CliError> {
    let located = |line: u64, key: Option<&str>, message: String| {
        CliError::Scenario(floe_scenario::ScenarioError::Input {
            file: path.to_path_buf(),
            line: line as usize,
            column: 1,
            key: key.map(str::to_string),
            message,
        })
    };
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| match e.into_kind() {
            csv::ErrorKind::Io(io) => CliError::io(path, io),
            other => located(1, None, format!("{other:?}")),
        })?;
    let headers = reader
        .headers()
        .map_err(|e| located(1, None, e.to_string()))?
        .clone();
    let find = |names: &[&str]| headers.iter().position(|h| names.contains(&h));
    let found = headers.iter().collect::<Vec<_>>().join(", ");
    let t_col = find(&TIME_COLUMNS).ok_or_else(|| {
        located(
            1,
            Some("t_s"),
            format!("missing time column (t_s, time_s or t); found: {found}"),
        )
    })?;
    let mu_col = find(&["mu"])
        .ok_or_else(|| located(1, Some("mu"), format!("missing column; found: {found}")))?;
    let (mut t, mut mu) = (Vec::new(), Vec::new());
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            located(line, None, e.to_string())
        })?;
        let line = record.position().map_or(0, |p| p.line());
        let number = |col: usize, name: &str| -> Result<f64, CliError> {
            let text = record.get(col).unwrap_or("");
            let x: f64 = text
                .parse()
                .map_err(|_| located(line, Some(name), format!("`{text}` is not a number")))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(located(
                    line,
                    Some(name),
                    format!("`{text}` is not a finite number"),
                ))
            }
        };
        let time = number(t_col, &headers[t_col])?;
        if let Some(&before) = t.last() {
            if time <= before {
                return Err(located(
                    line,
                    Some(&headers[t_col]),
                    format!("times must increase: {time} follows {before}"),
                ));
            }
        }
        t.push(time);
        mu.push(number(mu_col, "mu")?);
    }
    FitData::new(t, mu).map_err(|e| located(1, None, e.to_string()))
}
