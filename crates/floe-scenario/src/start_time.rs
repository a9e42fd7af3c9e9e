//! `start_time`, the UTC date of model time 0, read back from a scenario
//! text a run file stores (`/parameters/scenario_toml`), for outputs whose
//! time axis carries dates.

/// The stored scenario's `start_time` as a CF reference date
/// (`YYYY-MM-DD HH:MM:SS`, [`floe_basin::cf_time::cf_date`]), or `None`
/// where the scenario has none.
///
/// # Errors
/// A message where the text is not TOML or its `start_time` is not a date
/// (the scenario was read when the run began, so only an edited file gets
/// here).
pub fn stored_start_time(scenario_toml: &str) -> Result<Option<String>, String> {
    let table: toml::Table = scenario_toml.parse().map_err(|e: toml::de::Error| {
        format!("the stored scenario is not TOML: {}", e.message())
    })?;
    let Some(value) = table.get("start_time") else {
        return Ok(None);
    };
    value
        .as_str()
        .and_then(floe_basin::cf_time::cf_date)
        .map(Some)
        .ok_or_else(|| {
            format!(
                "the stored scenario's start_time = {value} is not a date and time like \
                 \"2024-03-01 00:00:00\" (UTC)"
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stored_start_time_is_read_as_a_cf_date() {
        let text =
            "title = \"t\"\nstart_time = \"2024-03-01T06:00:00Z\"\n[domain]\nsize_m = [1.0, 1.0]\n";
        assert_eq!(
            stored_start_time(text).unwrap().as_deref(),
            Some("2024-03-01 06:00:00")
        );
        assert_eq!(stored_start_time("title = \"t\"\n").unwrap(), None);
        assert_eq!(stored_start_time("").unwrap(), None);
        for bad in [
            "start_time = 3",
            "start_time = \"2024-02-30\"",
            "start_time = [",
        ] {
            assert!(stored_start_time(bad).is_err(), "{bad}");
        }
    }
}
