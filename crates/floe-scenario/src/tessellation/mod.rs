//! `[tessellation]`: the kinds of generated floes, one file each, listed in
//! [`KINDS`]. A kind owns its keys (which apply, their checks and
//! messages), its resolution (the keys into checked parameters) and its
//! generation (parameters into floes, with the build report's lines).
//! Adding a kind is its file, its line in [`KINDS`], and its keys as
//! fields of [`RawTessellation`] (serde reads them there, typed and
//! located). Messages that list the kinds take them from [`KINDS`].

mod diamond;
mod double_shear;
pub(crate) mod double_shear_geometry;
mod fill;
mod grid;
mod power_law;
mod voronoi;

use std::fmt::Debug;
use std::ops::Range;
use std::sync::Arc;

use floe_dem::contact_model::ContactModel;
use floe_dem::tessellation::{Rect, Tessellation, ThicknessDistribution};
use floe_dem::{DemError, Vec2};
use toml::Spanned;

use crate::domain::Domain;
use crate::error::ScenarioError;
use crate::extent::Extent;
use crate::numbers::{sig, thousands};
use crate::piece::Piece;
use crate::resolve::limits::{dem_error, refuse_given, within};
use crate::source_file::SourceFile;
use crate::spec::RawTessellation;

pub use voronoi::MAX_VORONOI_WORK;

/// Fraction of the nominal floe area below which generated floes (pieces
/// clipped at the domain edges) are dropped, unless the file says otherwise.
pub const DEFAULT_MIN_AREA_FRACTION: f64 = 0.1;

/// Most Lloyd iterations of a Voronoi tessellation, with or without
/// `size_distribution` (it converges in tens).
pub const MAX_RELAX_ITERATIONS: u64 = 10_000;

/// One kind of `[tessellation]`.
#[derive(Debug)]
pub(crate) struct Kind {
    /// Its `kind = "..."`.
    pub name: &'static str,
    /// The keys of `[tessellation]` that apply to it (`kind` aside).
    pub keys: &'static [&'static str],
    /// Its keys, checked, as what generates its floes.
    pub resolve: fn(&Keys<'_>) -> Result<Arc<dyn Generate>, ScenarioError>,
    /// Whether its floes are sea ice that `[ice]` grids may place and
    /// `[[land]]` may cover (not a laboratory set-up).
    pub sea_ice: bool,
}

/// Every kind, in the order messages list them.
pub(crate) const KINDS: &[Kind] = &[diamond::KIND, voronoi::KIND, grid::KIND, double_shear::KIND];

/// The kinds' names as the messages list them: "`a`, `b` or `c`".
pub(crate) fn names_text(kinds: impl Iterator<Item = &'static Kind>) -> String {
    let names: Vec<String> = kinds.map(|k| format!("`{}`", k.name)).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => names.concat(),
    }
}

/// A kind's resolved parameters: what generates its floes.
pub(crate) trait Generate: Debug + Send + Sync {
    /// The floes (free, and a set-up's prescribed blocks), with the build
    /// report's lines.
    fn generate(
        &self,
        g: &Generation<'_>,
        report: &mut Vec<String>,
    ) -> Result<Vec<Piece>, ScenarioError>;

    /// The double-shear set-up's load and sizes, when this is one.
    fn double_shear(&self) -> Option<&double_shear::DoubleShear> {
        None
    }
}

/// A resolved `[tessellation]`: its kind and parameters.
#[derive(Debug, Clone)]
pub(crate) struct Tessellated {
    pub kind: &'static Kind,
    pub floes: Arc<dyn Generate>,
}

/// What a kind's resolution reads: the table and where it is.
pub(crate) struct Keys<'a> {
    pub f: &'a SourceFile,
    pub t: &'a RawTessellation,
    /// Location of `[tessellation]`.
    pub span: Range<usize>,
    pub kind: &'static str,
    pub extent: Extent,
}

impl Keys<'_> {
    /// A key the kind needs is missing.
    pub fn need(&self, what: &str) -> ScenarioError {
        self.f.error(
            self.span.clone(),
            format!("tessellation.{what}"),
            format!("missing: kind `{}` needs it", self.kind),
        )
    }
}

/// What a kind's generation reads besides its parameters.
pub(crate) struct Generation<'a> {
    pub f: &'a SourceFile,
    /// Location of `[tessellation]`, blamed for what generation refuses.
    pub span: Range<usize>,
    /// The ice region: the domain minus the walls' insets.
    pub region: Rect,
    pub domain: Domain,
    pub seed: u64,
    pub thickness: ThicknessDistribution,
    pub min_area_fraction: f64,
    pub duration_s: f64,
    pub model: &'a ContactModel,
    /// Whether `[ice] concentration_grid` thins the floes.
    pub concentration_grid: bool,
    /// A tessellation's floes as free pieces, placed from the ice grids if
    /// any.
    pub place: &'a Place<'a>,
}

/// Makes a tessellation's floes free pieces, with report lines.
pub(crate) type Place<'a> =
    dyn Fn(Tessellation, &mut Vec<String>) -> Result<Vec<Piece>, ScenarioError> + 'a;

impl Generation<'_> {
    /// A [`DemError`] of the generator, blamed on `[tessellation]`.
    pub fn dem(&self, e: DemError) -> ScenarioError {
        dem_error(self.f, self.span.clone(), "tessellation", e)
    }

    /// The report line of the small pieces dropped.
    pub fn dropped_line(&self, what: &str, dropped: usize, area: f64) -> String {
        format!(
            "  {} {what} below {} of the nominal floe area dropped ({} m^2, {} % of the ice region)",
            thousands(dropped),
            self.min_area_fraction,
            sig(area),
            sig(100.0 * area / self.region.area_m2())
        )
    }
}

/// A rectangle of `size` centred on `center`, counter-clockwise.
pub(crate) fn rect_polygon(center: Vec2, size: [f64; 2]) -> Vec<Vec2> {
    let h = Vec2::new(0.5 * size[0], 0.5 * size[1]);
    vec![
        center - h,
        center + Vec2::new(h.x, -h.y),
        center + h,
        center + Vec2::new(-h.x, h.y),
    ]
}

/// `[tessellation]`: its kind from [`KINDS`], the keys that do not apply
/// to it refused, then the kind's own resolution. Returns the kind, the
/// table's location and `min_area_fraction`.
pub(crate) fn resolve(
    f: &SourceFile,
    raw: &Spanned<RawTessellation>,
    extent: Extent,
) -> Result<(Tessellated, Range<usize>, f64), ScenarioError> {
    let t = raw.get_ref();
    let span = raw.span();
    let Some(kind_word) = &t.kind else {
        return Err(f.error(
            span,
            "tessellation.kind",
            format!("missing: {}", names_text(KINDS.iter())),
        ));
    };
    let name = kind_word.get_ref().as_str();
    let Some(kind) = KINDS.iter().find(|k| k.name == name) else {
        return Err(f.error(
            kind_word.span(),
            "tessellation.kind",
            format!(
                "unknown kind `{name}`, expected {}",
                names_text(KINDS.iter())
            ),
        ));
    };
    refuse_given(
        f,
        "tessellation",
        &format!("kind `{name}`"),
        &t.given(),
        kind.keys,
    )?;
    let min_area_fraction = match &t.min_area_fraction {
        Some(v) => within(f, v, "tessellation.min_area_fraction", 0.0, 1.0, true)?,
        None => DEFAULT_MIN_AREA_FRACTION,
    };
    let keys = Keys {
        f,
        t,
        span: span.clone(),
        kind: kind.name,
        extent,
    };
    let floes = (kind.resolve)(&keys)?;
    Ok((Tessellated { kind, floes }, span, min_area_fraction))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every key of `[tessellation]` applies to some kind, and every kind's
    /// key is one of the table's: the table and the file's keys agree.
    #[test]
    fn the_kinds_keys_are_the_tables_keys() {
        let t: RawTessellation = toml::from_str("").unwrap();
        let table: Vec<&str> = t.given().iter().map(|(_, name)| *name).collect();
        for name in &table {
            assert!(
                KINDS.iter().any(|k| k.keys.contains(name)),
                "{name} applies to no kind"
            );
        }
        for k in KINDS {
            for key in k.keys {
                assert!(
                    table.contains(key),
                    "{} reads {key}, not in the table",
                    k.name
                );
            }
        }
    }

    /// docs/scenarios.md's `[tessellation]` table: its `kind` row names
    /// every kind, each kind's keys have a row that lists the kind, and
    /// the rows list no other kind.
    #[test]
    fn the_docs_table_names_every_kind_and_key() {
        let doc = include_str!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../docs/scenarios.md"
        ));
        let section = doc
            .split("## Floes: `[tessellation]`")
            .nth(1)
            .expect("the [tessellation] section");
        let rows: Vec<Vec<&str>> = section
            .lines()
            .skip_while(|l| !l.starts_with("| key |"))
            .skip(2)
            .take_while(|l| l.starts_with('|'))
            .map(|l| l.split('|').map(str::trim).collect())
            .collect();
        let kind_row = rows.iter().find(|r| r[1] == "`kind`").expect("kind row");
        for k in KINDS {
            assert!(
                kind_row[5].contains(&format!("\"{}\"", k.name)),
                "{}",
                k.name
            );
            for key in k.keys {
                let named = |cell: &str| {
                    cell.contains(&format!("`{key}`"))
                        || cell.contains(&format!("[[tessellation.{key}]]"))
                };
                assert!(
                    rows.iter()
                        .any(|r| named(r[1]) && r[2].split(", ").any(|name| name == k.name)),
                    "docs/scenarios.md has no row of {key} for {}",
                    k.name
                );
            }
        }
        for r in rows.iter().filter(|r| !r[2].is_empty()) {
            for name in r[2].split(", ") {
                assert!(KINDS.iter().any(|k| k.name == name), "{name} is no kind");
            }
        }
    }

    #[test]
    fn names_are_listed_as_a_sentence() {
        assert_eq!(
            names_text(KINDS.iter()),
            "`diamond`, `voronoi`, `grid` or `double-shear`"
        );
        assert_eq!(names_text(KINDS[..1].iter()), "`diamond`");
    }
}
