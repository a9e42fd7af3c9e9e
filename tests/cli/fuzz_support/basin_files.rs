//! Mutations of the basin scenario's own input files and of the keys that
//! name them: the NetCDF files truncated, emptied, filled with garbage,
//! with bytes flipped, given as another kind of file; the GeoJSON broken,
//! with non-finite or huge coordinates, other geometry types, no features,
//! holes, crossing rings; each file missing or a directory; the `file`
//! keys pointing at the wrong kind of file, at devices, at names with a
//! NUL. Each says what it did, what floe must do and what its message must
//! name.

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::base_inputs::{BASIN_FILES, BASIN_SCENARIO};
use super::Expect;

/// What becomes of one auxiliary file.
pub enum Content {
    Bytes(Vec<u8>),
    Missing,
    Directory,
}

pub struct BasinMutant {
    pub what: String,
    /// The scenario (changed by the cases that mutate its `file` keys).
    pub scenario: String,
    /// The auxiliary file changed, and how.
    pub change: Option<(&'static str, Content)>,
    pub expect: Expect,
    /// Text an exit-2 message must hold: the file or key it is about
    /// (empty: any).
    pub names: String,
}

fn base(name: &str) -> &'static [u8] {
    BASIN_FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, b)| *b)
        .expect("a basin file")
}

fn file_mutant(file: &'static str, what: &str, content: Content, expect: Expect) -> BasinMutant {
    BasinMutant {
        what: format!("{file}: {what}"),
        scenario: BASIN_SCENARIO.to_string(),
        change: Some((file, content)),
        expect,
        names: file.to_string(),
    }
}

/// The scenario with `old` (which it holds once) replaced by `new`.
fn scenario_mutant(old: &str, new: &str, names: &str, expect: Expect) -> BasinMutant {
    assert_eq!(
        BASIN_SCENARIO.matches(old).count(),
        1,
        "`{old}` is in the basin scenario once"
    );
    let shown = if new.len() > 80 {
        format!("{}... ({} characters)", &new[..60], new.len())
    } else {
        new.to_string()
    };
    BasinMutant {
        what: format!("scenario: `{old}` -> `{shown}`"),
        scenario: BASIN_SCENARIO.replacen(old, new, 1),
        change: None,
        expect,
        names: names.to_string(),
    }
}

/// Every fixed mutation, in a fixed order.
pub fn fixed_mutants() -> Vec<BasinMutant> {
    let mut all = Vec::new();
    for (name, other) in [("wind.nc", "ssh.nc"), ("ssh.nc", "wind.nc")] {
        all.extend(netcdf_mutants(name, other));
    }
    all.extend(geojson_mutants());
    all.extend(key_mutants());
    all
}

/// Never valid: missing, a directory, empty, cut short, garbage, another
/// kind of file; maybe valid: a header moved.
fn netcdf_mutants(name: &'static str, other: &'static str) -> Vec<BasinMutant> {
    use Expect::{Anything, Refusal};
    let bytes = base(name);
    let n = bytes.len();
    // A fixed stream, so that the fixed mutations do not depend on the seed.
    let mut noise = ChaCha8Rng::seed_from_u64(n as u64);
    let garbage: Vec<u8> = (0..n).map(|_| noise.gen()).collect();
    let mut after_magic = garbage.clone();
    after_magic[..8].copy_from_slice(&bytes[..8]);
    let mut bad_magic = bytes.to_vec();
    bad_magic[3] ^= 0x0C;
    let mut m = vec![
        file_mutant(name, "missing", Content::Missing, Refusal),
        file_mutant(name, "a directory", Content::Directory, Refusal),
        file_mutant(name, "empty (0 bytes)", Content::Bytes(Vec::new()), Refusal),
        file_mutant(name, "its first 4 bytes only", cut(bytes, 4), Refusal),
        file_mutant(name, "cut to half its length", cut(bytes, n / 2), Refusal),
        file_mutant(name, "its last 100 bytes cut", cut(bytes, n - 100), Refusal),
        file_mutant(name, "its last byte cut", cut(bytes, n - 1), Refusal),
        file_mutant(name, "every byte random", Content::Bytes(garbage), Refusal),
        file_mutant(
            name,
            "random bytes after its 8-byte signature",
            Content::Bytes(after_magic),
            Refusal,
        ),
        file_mutant(
            name,
            "its signature's fourth byte changed",
            Content::Bytes(bad_magic),
            Refusal,
        ),
        file_mutant(
            name,
            "the GeoJSON file's bytes",
            Content::Bytes(base("coast.geojson").to_vec()),
            Refusal,
        ),
        file_mutant(
            name,
            &format!("the bytes of {other} (without the variables asked for)"),
            Content::Bytes(base(other).to_vec()),
            Refusal,
        ),
        file_mutant(
            name,
            "the scenario's bytes",
            Content::Bytes(BASIN_SCENARIO.as_bytes().to_vec()),
            Refusal,
        ),
        file_mutant(
            name,
            "an HDF5 signature prepended",
            prepend(b"\x89HDF\r\n\x1a\n", bytes),
            Refusal,
        ),
        // HDF5 looks for its superblock at 0, 512, 1024, ...: a 512-byte
        // user block may be valid.
        file_mutant(
            name,
            "512 zero bytes prepended",
            prepend(&[0; 512], bytes),
            Anything,
        ),
    ];
    if name == "ssh.nc" {
        m.extend(classic_header_mutants(name, bytes));
    } else {
        m.push(file_mutant(
            name,
            "every `u10` renamed `u1x` (HDF5 names and heaps)",
            replace_all(bytes, b"u10", b"u1x"),
            Anything,
        ));
        // One byte of the global heap that holds the dimension scales'
        // references: HDF5 1.10.8 (Debian 12) crashes (SIGSEGV) on the
        // first, loops for ever on the second (found by the random cases).
        for (at, value, what) in [(6459, 0xE1, "crashes"), (6578, 0xA0, "loops")] {
            let mut b = bytes.to_vec();
            b[at] = value;
            m.push(file_mutant(
                name,
                &format!("byte {at} set to {value:#04x} (HDF5 1.10 {what} on it)"),
                Content::Bytes(b),
                Anything,
            ));
        }
    }
    m
}

/// NetCDF-3 classic: dimension lengths and a variable's name changed in the
/// header (`y` is its first dimension, `x` its second).
fn classic_header_mutants(name: &'static str, bytes: &[u8]) -> Vec<BasinMutant> {
    use Expect::Refusal;
    let length_at = |dim: u8| {
        let tag = [0, 0, 0, 1, dim, 0, 0, 0];
        bytes.windows(8).position(|w| w == tag).expect("dimension") + 8
    };
    let with_length = |dim: u8, len: u32| {
        let mut b = bytes.to_vec();
        let at = length_at(dim);
        b[at..at + 4].copy_from_slice(&len.to_be_bytes());
        Content::Bytes(b)
    };
    vec![
        file_mutant(
            name,
            "dimension y's length set to 2^31 - 1",
            with_length(b'y', i32::MAX as u32),
            Refusal,
        ),
        file_mutant(
            name,
            "dimension x's length set to 2^31 - 1",
            with_length(b'x', i32::MAX as u32),
            Refusal,
        ),
        file_mutant(
            name,
            "dimension y's length set to 0 (the record dimension)",
            with_length(b'y', 0),
            Refusal,
        ),
        file_mutant(
            name,
            "dimension x's length set to 1",
            with_length(b'x', 1),
            Refusal,
        ),
        file_mutant(
            name,
            "variable `zos` renamed `zoz` in the header",
            replace_all(bytes, b"zos", b"zoz"),
            Refusal,
        ),
    ]
}

fn cut(bytes: &[u8], len: usize) -> Content {
    Content::Bytes(bytes[..len].to_vec())
}

fn prepend(head: &[u8], bytes: &[u8]) -> Content {
    let mut b = head.to_vec();
    b.extend_from_slice(bytes);
    Content::Bytes(b)
}

fn replace_all(bytes: &[u8], old: &[u8], new: &[u8]) -> Content {
    assert_eq!(old.len(), new.len());
    let mut b = bytes.to_vec();
    let mut i = 0;
    while i + old.len() <= b.len() {
        if &b[i..i + old.len()] == old {
            b[i..i + old.len()].copy_from_slice(new);
            i += old.len();
        } else {
            i += 1;
        }
    }
    Content::Bytes(b)
}

/// The island's vertices (longitude, latitude, as written), the closing one
/// included.
fn island() -> Vec<(String, String)> {
    let text = std::str::from_utf8(base("coast.geojson")).expect("UTF-8");
    text.lines()
        .map(str::trim)
        .filter(|l| l.starts_with('[') && !l.starts_with("[["))
        .map(|l| {
            let inner = l.trim_end_matches(',').trim_start_matches('[');
            let inner = inner.trim_end_matches(']');
            let (lon, lat) = inner.split_once(',').expect("lon, lat");
            (lon.trim().to_string(), lat.trim().to_string())
        })
        .collect()
}

fn ring(vertices: &[(String, String)]) -> String {
    let p: Vec<String> = vertices
        .iter()
        .map(|(a, b)| format!("[{a}, {b}]"))
        .collect();
    format!("[{}]", p.join(", "))
}

fn polygon(rings: &[String]) -> String {
    format!(
        "{{\"type\": \"Polygon\", \"coordinates\": [{}]}}",
        rings.join(", ")
    )
}

fn feature(geometry: &str) -> String {
    format!("{{\"type\": \"Feature\", \"properties\": {{}}, \"geometry\": {geometry}}}")
}

fn collection(features: &[String]) -> String {
    format!(
        "{{\"type\": \"FeatureCollection\", \"features\": [{}]}}\n",
        features.join(", ")
    )
}

/// A collection of the island with its vertices changed by `edit`.
fn island_edited(edit: impl FnOnce(&mut Vec<(String, String)>)) -> Content {
    let mut v = island();
    edit(&mut v);
    geojson(&collection(&[feature(&polygon(&[ring(&v)]))]))
}

fn geojson(text: &str) -> Content {
    Content::Bytes(text.as_bytes().to_vec())
}

fn geojson_mutants() -> Vec<BasinMutant> {
    use Expect::{Anything, Refusal, Success};
    const F: &str = "coast.geojson";
    let bytes = base(F);
    let text = std::str::from_utf8(bytes).expect("UTF-8");
    let n = bytes.len();
    let island_ring = ring(&island());
    let island_polygon = polygon(std::slice::from_ref(&island_ring));
    // Vertex `k` (the first also closes the ring) given new coordinates.
    let set = |k: usize, lon: Option<&str>, lat: Option<&str>| {
        let (lon, lat) = (lon.map(String::from), lat.map(String::from));
        island_edited(move |v| {
            let closing = v.len() - 1;
            let at = if k == 0 { vec![0, closing] } else { vec![k] };
            for i in at {
                if let Some(a) = &lon {
                    v[i].0 = a.clone();
                }
                if let Some(b) = &lat {
                    v[i].1 = b.clone();
                }
            }
        })
    };
    let hole = {
        // A small triangle inside the island's lower bar.
        let v = island();
        let f = |s: &str| s.parse::<f64>().expect("a coordinate");
        let corners = [&v[0], &v[1], &v[5]];
        let c = corners.iter().fold((0.0, 0.0), |s, p| {
            (s.0 + f(&p.0) / 3.0, s.1 + f(&p.1) / 3.0)
        });
        let mut t: Vec<(String, String)> = corners
            .iter()
            .map(|p| {
                (
                    format!("{:.7}", c.0 + 0.5 * (f(&p.0) - c.0)),
                    format!("{:.7}", c.1 + 0.5 * (f(&p.1) - c.1)),
                )
            })
            .collect();
        t.push(t[0].clone());
        ring(&t)
    };
    let line_string = format!("{{\"type\": \"LineString\", \"coordinates\": {island_ring}}}");
    let deep = format!(
        "{{\"type\": \"Polygon\", \"coordinates\": {}{}}}",
        "[".repeat(20_000),
        "]".repeat(20_000)
    );
    let mut not_utf8 = bytes.to_vec();
    not_utf8.insert(n / 2, 0xFF);
    let mut bom = b"\xEF\xBB\xBF".to_vec();
    bom.extend_from_slice(bytes);
    vec![
        file_mutant(F, "missing", Content::Missing, Refusal),
        file_mutant(F, "a directory", Content::Directory, Refusal),
        file_mutant(F, "empty (0 bytes)", Content::Bytes(Vec::new()), Refusal),
        file_mutant(F, "cut to a third", cut(bytes, n / 3), Refusal),
        file_mutant(F, "cut to two thirds", cut(bytes, 2 * n / 3), Refusal),
        file_mutant(
            F,
            "its last `}` dropped",
            geojson(&text[..text.rfind('}').expect("}")]),
            Refusal,
        ),
        file_mutant(
            F,
            "a trailing comma in the ring",
            geojson(&text.replacen("]\n  ]]", "],\n  ]]", 1)),
            Refusal,
        ),
        file_mutant(
            F,
            "a byte that is not UTF-8",
            Content::Bytes(not_utf8),
            Refusal,
        ),
        file_mutant(
            F,
            "a UTF-8 byte-order mark first",
            Content::Bytes(bom),
            Success,
        ),
        file_mutant(F, "JSON `[]`", geojson("[]"), Refusal),
        file_mutant(F, "JSON `{}`", geojson("{}"), Refusal),
        file_mutant(F, "a JSON string", geojson("\"coast\""), Refusal),
        file_mutant(
            F,
            "a Feature without geometry key",
            geojson("{\"type\": \"Feature\", \"properties\": {}}"),
            Refusal,
        ),
        file_mutant(
            F,
            "a TopoJSON Topology",
            geojson("{\"type\": \"Topology\", \"objects\": {}, \"arcs\": []}"),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 2's longitude NaN",
            set(2, Some("NaN"), None),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 2's latitude -Infinity",
            set(2, None, Some("-Infinity")),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 3's longitude 1e400",
            set(3, Some("1e400"), None),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 3's latitude 1e300",
            set(3, None, Some("1e300")),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 4's longitude -1e300",
            set(4, Some("-1e300"), None),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 4's latitude 1e12",
            set(4, None, Some("1e12")),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 0 (and the closing vertex) at longitude 1e308",
            set(0, Some("1e308"), None),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 5's latitude 91",
            set(5, None, Some("91")),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 5's latitude 90 (the pole)",
            set(5, None, Some("90")),
            Anything,
        ),
        file_mutant(
            F,
            "vertex 6's longitude 4.9e-324",
            set(6, Some("4.9e-324"), None),
            Anything,
        ),
        file_mutant(
            F,
            "vertex 6's longitude null",
            set(6, Some("null"), None),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 6's latitude a string",
            set(6, None, Some("\"81\"")),
            Refusal,
        ),
        file_mutant(
            F,
            "vertex 7 with one coordinate",
            island_edited(|v| v[7].1 = String::new()),
            Refusal,
        ),
        file_mutant(
            F,
            "every vertex with an altitude",
            island_edited(|v| v.iter_mut().for_each(|p| p.1.push_str(", 12.5"))),
            Success,
        ),
        file_mutant(
            F,
            "the island's longitudes + 10 (off the domain)",
            island_edited(|v| {
                for p in v.iter_mut() {
                    p.0 = format!("{:.7}", p.0.parse::<f64>().expect("lon") + 10.0);
                }
            }),
            Anything,
        ),
        file_mutant(
            F,
            "the ring reversed (clockwise)",
            island_edited(|v| v.reverse()),
            Success,
        ),
        file_mutant(
            F,
            "the closing vertex dropped",
            island_edited(|v| {
                v.pop();
            }),
            Anything,
        ),
        file_mutant(
            F,
            "vertex 3 repeated",
            island_edited(|v| v.insert(3, v[3].clone())),
            Anything,
        ),
        file_mutant(
            F,
            "vertices 1 and 2 swapped (edges cross)",
            island_edited(|v| v.swap(1, 2)),
            Refusal,
        ),
        file_mutant(
            F,
            "every vertex the first",
            island_edited(|v| {
                let first = v[0].clone();
                v.iter_mut().for_each(|p| *p = first.clone());
            }),
            Refusal,
        ),
        file_mutant(
            F,
            "a ring of two distinct vertices",
            island_edited(|v| {
                let (a, b) = (v[0].clone(), v[1].clone());
                *v = vec![a.clone(), b, a];
            }),
            Refusal,
        ),
        file_mutant(
            F,
            "a hole in the island",
            geojson(&collection(&[feature(&polygon(&[
                island_ring.clone(),
                hole,
            ]))])),
            Refusal,
        ),
        file_mutant(
            F,
            "the ring as a LineString",
            geojson(&collection(&[feature(&line_string)])),
            Refusal,
        ),
        file_mutant(
            F,
            "`Polygon` retyped `LineString` (its coordinates nested too deep)",
            geojson(&text.replacen("\"Polygon\"", "\"LineString\"", 1)),
            Refusal,
        ),
        file_mutant(
            F,
            "`Polygon` retyped `polygon`",
            geojson(&text.replacen("\"Polygon\"", "\"polygon\"", 1)),
            Refusal,
        ),
        file_mutant(
            F,
            "a Point",
            geojson(&collection(&[feature(
                "{\"type\": \"Point\", \"coordinates\": [-62.0, 81.0]}",
            )])),
            Refusal,
        ),
        file_mutant(
            F,
            "the island and a Point",
            geojson(&collection(&[
                feature(&island_polygon),
                feature("{\"type\": \"Point\", \"coordinates\": [-62.0, 81.0]}"),
            ])),
            Refusal,
        ),
        file_mutant(
            F,
            "the island in a GeometryCollection",
            geojson(&collection(&[feature(&format!(
                "{{\"type\": \"GeometryCollection\", \"geometries\": [{island_polygon}]}}"
            ))])),
            Refusal,
        ),
        file_mutant(
            F,
            "the island as a MultiPolygon",
            geojson(&collection(&[feature(&format!(
                "{{\"type\": \"MultiPolygon\", \"coordinates\": [[{island_ring}]]}}"
            ))])),
            Success,
        ),
        file_mutant(
            F,
            "the island as a bare Polygon",
            geojson(&island_polygon),
            Success,
        ),
        file_mutant(
            F,
            "the island as a single Feature",
            geojson(&feature(&island_polygon)),
            Success,
        ),
        file_mutant(
            F,
            "an empty FeatureCollection",
            geojson(&collection(&[])),
            Refusal,
        ),
        file_mutant(
            F,
            "a feature with null geometry",
            geojson(&collection(&[feature("null")])),
            Refusal,
        ),
        file_mutant(F, "coordinates nested 20000 deep", geojson(&deep), Refusal),
        file_mutant(
            F,
            "the bytes of ssh.nc",
            Content::Bytes(base("ssh.nc").to_vec()),
            Refusal,
        ),
    ]
}

/// The scenario's `file`, `variables`, `coordinates`, `projection` and
/// `start_time` values changed.
fn key_mutants() -> Vec<BasinMutant> {
    use Expect::{Anything, Refusal, Success};
    let long = format!("{}.nc", "a".repeat(5000));
    let mut m = Vec::new();
    for (old, key, others) in [
        (
            "file = \"coast.geojson\"",
            "land[0].file",
            &["wind.nc", "ssh.nc", "case.toml"][..],
        ),
        (
            "file = \"wind.nc\"",
            "wind.file",
            &["coast.geojson", "ssh.nc", "case.toml"][..],
        ),
        (
            "file = \"ssh.nc\"",
            "ocean.sea_surface_height",
            &["coast.geojson", "wind.nc", "case.toml"][..],
        ),
    ] {
        let mut paths = vec![
            "",
            " ",
            "missing.file",
            ".",
            "..",
            "/",
            "/dev/null",
            "/dev/zero",
            "/proc/self/mem",
            "a\\u0000b",
            "wind.nc/",
            long.as_str(),
        ];
        paths.extend_from_slice(others);
        for path in paths {
            m.push(scenario_mutant(
                old,
                &format!("file = \"{path}\""),
                key,
                Refusal,
            ));
        }
    }
    let wind = "variables = [\"u10\", \"v10\"]";
    for (new, expect) in [
        ("[\"v10\", \"u10\"]", Success),
        ("[\"u10\", \"u10\"]", Anything),
        ("[\"u10\", \"U10\"]", Refusal),
        ("[\"time\", \"v10\"]", Refusal),
        ("[\"latitude\", \"longitude\"]", Refusal),
        ("[\"u10\", \"\"]", Refusal),
        ("[\"u10\", \"v10\", \"u10\"]", Refusal),
    ] {
        m.push(scenario_mutant(
            wind,
            &format!("variables = {new}"),
            "wind",
            expect,
        ));
    }
    for (new, expect) in [
        ("\"x\"", Refusal),
        ("\"y\"", Refusal),
        ("\"time\"", Refusal),
        ("\"\"", Refusal),
        ("\"zos\\u0000\"", Refusal),
    ] {
        m.push(scenario_mutant(
            "variable = \"zos\"",
            &format!("variable = {new}"),
            "sea_surface_height",
            expect,
        ));
    }
    m.push(scenario_mutant(
        "coordinates = \"lonlat\"",
        "coordinates = \"xy\"",
        "land[0]",
        Anything,
    ));
    for (new, expect) in [
        ("\"EPSG:4326\"", Refusal),
        ("\"EPSG:99999\"", Refusal),
        (
            "\"+proj=stere +lat_0=90 +lat_ts=70 +lon_0=-45 +datum=WGS84 +units=m\"",
            Success,
        ),
        ("\"+proj=nonsense\"", Refusal),
        ("\"\"", Refusal),
    ] {
        m.push(scenario_mutant(
            "projection = \"EPSG:3413\"",
            &format!("projection = {new}"),
            "map.projection",
            expect,
        ));
    }
    // The South Pole's plane: the domain lands far from the wind's grid,
    // which the message may name rather than the projection.
    m.push(scenario_mutant(
        "projection = \"EPSG:3413\"",
        "projection = \"EPSG:3031\"",
        "",
        Anything,
    ));
    let start = "start_time = \"2024-03-01 00:00:00\"";
    for (new, names, expect) in [
        // the wind file's times do not cover the run
        ("\"2024-02-29 23:59:00\"", "wind", Refusal),
        ("\"2024-03-01 05:55:00\"", "wind", Refusal),
        ("\"1900-01-01 00:00:00\"", "wind", Refusal),
        ("\"2024-03-01 00:30:00\"", "wind", Success),
        ("\"2024-02-30 00:00:00\"", "start_time", Refusal),
        ("\"2024-03-01 24:00:00\"", "start_time", Refusal),
        ("\"yesterday\"", "start_time", Refusal),
        ("\"\"", "start_time", Refusal),
    ] {
        m.push(scenario_mutant(
            start,
            &format!("start_time = {new}"),
            names,
            expect,
        ));
    }
    m
}

/// A seeded mutation: bytes of a NetCDF file changed at random, or bytes of
/// the GeoJSON changed, inserted or deleted. Such a file may still be
/// valid (a value changed), so anything may come of it, but an exit 2 must
/// name the file.
pub fn random_mutant(rng: &mut ChaCha8Rng) -> BasinMutant {
    let name = *["wind.nc", "ssh.nc", "coast.geojson"]
        .choose(rng)
        .expect("files");
    let mut bytes = base(name).to_vec();
    let what = if name == "coast.geojson" {
        let at = rng.gen_range(0..bytes.len());
        let byte = *b"0123456789.,-[]{}\": eE".choose(rng).expect("bytes");
        match rng.gen_range(0..3) {
            0 => {
                let old = bytes[at];
                bytes[at] = byte;
                format!("byte {at} `{}` -> `{}`", old as char, byte as char)
            }
            1 => {
                bytes.insert(at, byte);
                format!("`{}` inserted at byte {at}", byte as char)
            }
            _ => {
                let old = bytes.remove(at);
                format!("byte {at} `{}` deleted", old as char)
            }
        }
    } else if rng.gen_bool(0.5) {
        let k = rng.gen_range(1..=4);
        let mut changed = Vec::new();
        for _ in 0..k {
            let at = rng.gen_range(0..bytes.len());
            bytes[at] = rng.gen();
            changed.push(format!("{at} -> {:#04x}", bytes[at]));
        }
        format!("bytes changed: {}", changed.join(", "))
    } else {
        let len = rng.gen_range(8..=256).min(bytes.len());
        let at = rng.gen_range(0..=bytes.len() - len);
        bytes[at..at + len].iter_mut().for_each(|b| *b = rng.gen());
        format!("bytes {at}..{} random", at + len)
    };
    file_mutant(name, &what, Content::Bytes(bytes), Expect::Anything)
}
