//! The initial ice's gridded fields: sea-ice concentration (a fraction or
//! percent) and thickness (m), read as [`ScalarGrid`]s and checked.
//!
//! **Concentration units.** The variable's `units` attribute decides:
//! `%`, `percent` → percent; `1`, `fraction`, `dimensionless`, `0-1` →
//! fraction (CF's canonical unit of `sea_ice_area_fraction` is `1`).
//! Without the attribute (or empty), the values decide: a largest value
//! above 1.5 is percent, otherwise a fraction. Refused as ambiguous: a
//! fraction by its units with values above 1.5, percent by its units with
//! no value above 1.5 (a fraction labelled percent, or a domain with
//! almost no ice); the caller may then state the units itself. Other
//! units are refused. After conversion every value must lie in `[0, 1]`
//! (rounding of up to 1e-6 is clipped).
//!
//! **Thickness units.** `m` (or `meter(s)`, `metre(s)`, or none) and `cm`.

use crate::cf_file::CfFile;
use crate::error::BasinError;
use crate::scalar_grid::{ScalarGrid, ScalarRequest};

/// How a concentration is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConcentrationUnits {
    /// A fraction in `[0, 1]`.
    Fraction,
    /// Percent, `[0, 100]`.
    Percent,
}

impl ConcentrationUnits {
    /// `"fraction"` or `"percent"`.
    pub fn name(self) -> &'static str {
        match self {
            ConcentrationUnits::Fraction => "fraction",
            ConcentrationUnits::Percent => "percent",
        }
    }
}

/// Largest value of a fraction read as such when the units are not given.
pub const PERCENT_THRESHOLD: f64 = 1.5;

/// Rounding tolerated beyond `[0, 1]` (clipped), as a fraction.
const ROUNDING: f64 = 1e-6;

/// A concentration field, as a fraction.
#[derive(Debug, Clone)]
pub struct ConcentrationGrid {
    /// The values, converted to a fraction.
    pub field: ScalarGrid,
    /// The units the file's values were in.
    pub units: ConcentrationUnits,
    /// How the units were decided, for the report (`units "%"`, `stated
    /// in the scenario`, `no units attribute; largest value 97`).
    pub units_reason: String,
}

/// Reads a concentration (see the module docs). `units`: the caller's own
/// statement of the units, which overrides the attribute.
///
/// # Errors
/// As [`ScalarGrid::open`]; units that are not a concentration's, or
/// ambiguous; a value outside `[0, 1]` after conversion (naming it and
/// where it is).
pub fn open_concentration(
    request: ScalarRequest<'_>,
    units: Option<ConcentrationUnits>,
) -> Result<ConcentrationGrid, BasinError> {
    let mut field = ScalarGrid::open(request)?;
    let err = |why: String| BasinError::File {
        path: request.path.to_path_buf(),
        why: format!("variable \"{}\": {why}", request.variable),
    };
    let attribute = CfFile::open(request.path)?.text_attribute(request.variable, "units");
    let largest = field.extremes().map_or(0.0, |(_, hi)| hi.0);
    let stated = attribute
        .as_deref()
        .map(str::trim)
        .filter(|u| !u.is_empty());
    let (units, units_reason) = match (units, stated) {
        (Some(u), _) => (u, format!("{} as stated in the scenario", u.name())),
        (None, None) => {
            let u = if largest > PERCENT_THRESHOLD {
                ConcentrationUnits::Percent
            } else {
                ConcentrationUnits::Fraction
            };
            (
                u,
                format!("{}: no units attribute, largest value {largest}", u.name()),
            )
        }
        (None, Some(word)) => {
            let u = match word.to_ascii_lowercase().as_str() {
                "%" | "percent" | "percentage" => ConcentrationUnits::Percent,
                "1" | "fraction" | "dimensionless" | "0-1" | "-" => ConcentrationUnits::Fraction,
                _ => {
                    return Err(err(format!(
                        "units \"{word}\" are not a concentration's: floe reads a fraction \
                         (units \"1\") or percent (units \"%\")"
                    )))
                }
            };
            let hint = "state the units in the scenario (units = \"fraction\" or \"percent\")";
            if u == ConcentrationUnits::Fraction && largest > PERCENT_THRESHOLD {
                return Err(err(format!(
                    "units \"{word}\" say a fraction, but values reach {largest}: percent? \
                     The units are ambiguous; {hint}"
                )));
            }
            if u == ConcentrationUnits::Percent && largest > 0.0 && largest <= PERCENT_THRESHOLD {
                return Err(err(format!(
                    "units \"{word}\" say percent, but no value is above {largest}: a fraction? \
                     The units are ambiguous; {hint}"
                )));
            }
            (u, format!("{} (units \"{word}\")", u.name()))
        }
    };
    let scale = match units {
        ConcentrationUnits::Fraction => 1.0,
        ConcentrationUnits::Percent => 0.01,
    };
    field.map_values(|v| v * scale);
    if let Some(((lo, klo), (hi, khi))) = field.extremes() {
        for (v, k) in [(lo, klo), (hi, khi)] {
            if !(-ROUNDING..=1.0 + ROUNDING).contains(&v) {
                let p = field.node_position(k);
                let (shown, range) = match units {
                    ConcentrationUnits::Fraction => (v, "[0, 1]"),
                    ConcentrationUnits::Percent => (v * 100.0, "[0, 100] %"),
                };
                return Err(err(format!(
                    "concentration {shown} at ({:.1}, {:.1}) m is outside {range} (read as {})",
                    p.x, p.y, units_reason
                )));
            }
        }
        field.map_values(|v| v.clamp(0.0, 1.0));
    }
    Ok(ConcentrationGrid {
        field,
        units,
        units_reason,
    })
}

/// Reads a thickness in metres (see the module docs); values `≤ 0` and
/// missing ones are kept as they are, for the caller to drop floes there.
///
/// # Errors
/// As [`ScalarGrid::open`]; units that are not a length's.
pub fn open_thickness(request: ScalarRequest<'_>) -> Result<ScalarGrid, BasinError> {
    let attribute = CfFile::open(request.path)?.text_attribute(request.variable, "units");
    let scale = match attribute.as_deref().map(str::trim).unwrap_or("") {
        "" | "m" | "meter" | "meters" | "metre" | "metres" => 1.0,
        "cm" | "centimeter" | "centimeters" | "centimetre" | "centimetres" => 0.01,
        other => {
            return Err(BasinError::File {
                path: request.path.to_path_buf(),
                why: format!(
                    "variable \"{}\": units \"{other}\" are not a thickness's: floe reads m or cm",
                    request.variable
                ),
            })
        }
    };
    let mut field = ScalarGrid::open(request)?;
    if scale != 1.0 {
        field.map_values(|v| v * scale);
    }
    Ok(field)
}
