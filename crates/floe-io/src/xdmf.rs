//! A run file as ParaView reads it: an XDMF 3 description (`RUN.xdmf`)
//! whose fields point into the run file itself (HDF5 hyperslabs of each
//! snapshot's rows, nothing copied), and a sidecar (`RUN.xdmf.h5`) with
//! only what the run file does not hold: each snapshot's floe polygons in
//! world coordinates (the file stores them in each floe's frame), each floe
//! set's polygon connectivity, the contacts' line ends and each floe's
//! mean contact state.
//!
//! Three temporal collections: `floes` (every floe as a polygon cell, with
//! velocity, spin, thickness, mass, area, id, prescribed, land, stress
//! where the run has it, and the mean `theta` and `mu` of its contacts),
//! `walls` (the prescribed floes alone: walls and land) and `contacts` (a
//! line from floe `a`'s centroid to floe `b`'s image nearest to it, with the
//! contact's forces, `mu`, `theta` and slip rate).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{invalid, Context, IoError};
use crate::reader::{ContactSnapshot, RunFile, StaticFloes};
use crate::{h5, layout};

/// What [`write_xdmf`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct XdmfExport {
    /// The XDMF file.
    pub xdmf: PathBuf,
    /// The sidecar HDF5 file with the polygons in world coordinates.
    pub sidecar: PathBuf,
    /// Snapshots described.
    pub snapshots: usize,
}

/// The sidecar's path for the XDMF file `xdmf`: `RUN.xdmf.h5`.
pub fn sidecar_path(xdmf: &Path) -> PathBuf {
    let mut name = xdmf.file_name().unwrap_or_default().to_os_string();
    name.push(".h5");
    xdmf.with_file_name(name)
}

/// Writes `xdmf` (and its sidecar, [`sidecar_path`]) describing every
/// complete snapshot of the run file `run`. Existing outputs are replaced
/// only with `force`; both are written under temporary names and renamed
/// at the end, so a failure leaves neither half-written.
pub fn write_xdmf(run: &Path, xdmf: &Path, force: bool) -> Result<XdmfExport, IoError> {
    let file = RunFile::open(run)?;
    let sidecar = sidecar_path(xdmf);
    for out in [xdmf, sidecar.as_path()] {
        if out.exists() && !force {
            return Err(IoError::AlreadyExists {
                path: out.to_path_buf(),
            });
        }
        if same_file(out, run) {
            return Err(invalid(
                out,
                format!("would overwrite the run file {}", run.display()),
            ));
        }
    }
    let part = |p: &Path| {
        let mut name = p.file_name().unwrap_or_default().to_os_string();
        name.push(".part");
        p.with_file_name(name)
    };
    let (xdmf_part, sidecar_part) = (part(xdmf), part(&sidecar));
    let _ = std::fs::remove_file(&sidecar_part);
    let result = describe(&file, run, xdmf, &sidecar, &sidecar_part);
    let written = result.and_then(|(text, snapshots)| {
        std::fs::write(&xdmf_part, text).map_err(|e| cannot_create(xdmf, e))?;
        std::fs::rename(&sidecar_part, &sidecar).map_err(|e| cannot_create(&sidecar, e))?;
        std::fs::rename(&xdmf_part, xdmf).map_err(|e| cannot_create(xdmf, e))?;
        Ok(snapshots)
    });
    match written {
        Ok(snapshots) => Ok(XdmfExport {
            xdmf: xdmf.to_path_buf(),
            sidecar,
            snapshots,
        }),
        Err(e) => {
            let _ = std::fs::remove_file(&xdmf_part);
            let _ = std::fs::remove_file(&sidecar_part);
            Err(e)
        }
    }
}

/// Whether `a` and `b` name one existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    matches!(
        (std::fs::canonicalize(a), std::fs::canonicalize(b)),
        (Ok(ca), Ok(cb)) if ca == cb
    )
}

fn cannot_create(path: &Path, e: std::io::Error) -> IoError {
    IoError::CannotCreate {
        path: path.to_path_buf(),
        reason: e.to_string(),
    }
}

/// How the XDMF names a file: by its name when it sits beside the XDMF
/// file, else by its absolute path.
fn reference(target: &Path, xdmf: &Path) -> String {
    let dir = |p: &Path| {
        std::path::absolute(p)
            .ok()
            .and_then(|a| a.parent().map(Path::to_path_buf))
    };
    match (dir(target), dir(xdmf)) {
        (Some(a), Some(b)) if a == b => target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        _ => std::path::absolute(target)
            .unwrap_or_else(|_| target.to_path_buf())
            .display()
            .to_string(),
    }
}

/// `text` as XML character data (a file name may hold `&` or `<`).
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// An HDF5 element type as XDMF names it.
#[derive(Clone, Copy)]
enum Number {
    F64,
    U64,
    U8,
    I64,
}

impl Number {
    fn attributes(self) -> &'static str {
        match self {
            Number::F64 => r#"NumberType="Float" Precision="8""#,
            Number::U64 => r#"NumberType="UInt" Precision="8""#,
            Number::U8 => r#"NumberType="UChar" Precision="1""#,
            Number::I64 => r#"NumberType="Int" Precision="8""#,
        }
    }
}

fn dims(d: &[usize]) -> String {
    d.iter().map(usize::to_string).collect::<Vec<_>>().join(" ")
}

/// A whole dataset of `file`.
fn whole(file: &str, path: &str, number: Number, shape: &[usize]) -> String {
    format!(
        r#"<DataItem Dimensions="{}" {} Format="HDF">{file}:/{path}</DataItem>"#,
        dims(shape),
        number.attributes()
    )
}

/// Rows `first .. first + count` of the first axis of a dataset of shape
/// `shape` (its other axes whole), the item shaped `out`.
fn slab(
    file: &str,
    path: &str,
    number: Number,
    shape: &[usize],
    (first, count): (usize, usize),
    out: &[usize],
) -> String {
    let rank = shape.len();
    let mut start = vec![0; rank];
    let mut size = shape.to_vec();
    start[0] = first;
    size[0] = count;
    format!(
        r#"<DataItem ItemType="HyperSlab" Dimensions="{}" Type="HyperSlab"><DataItem Dimensions="3 {rank}" Format="XML">{} {} {}</DataItem>{}</DataItem>"#,
        dims(out),
        dims(&start),
        dims(&vec![1; rank]),
        dims(&size),
        whole(file, path, number, shape)
    )
}

/// Rows `first .. first + count`, shaped `[count, rest...]`.
fn rows(
    file: &str,
    path: &str,
    number: Number,
    shape: &[usize],
    first: usize,
    count: usize,
) -> String {
    let out: Vec<usize> = std::iter::once(count)
        .chain(shape[1..].iter().copied())
        .collect();
    slab(file, path, number, shape, (first, count), &out)
}

/// Row `row` of a `[S, n, ...]` snapshot element, shaped `[n, ...]`.
fn snapshot_row(file: &str, path: &str, shape: &[usize], row: usize) -> String {
    slab(file, path, Number::F64, shape, (row, 1), &shape[1..])
}

fn attribute(name: &str, kind: &str, item: &str) -> String {
    format!(r#"<Attribute Name="{name}" AttributeType="{kind}" Center="Cell">{item}</Attribute>"#)
}

/// Polygon connectivity of the floes `keep` picks, for an XDMF `Mixed`
/// topology: per floe, 3 (a polygon), its vertex count and its vertices'
/// indices into the snapshot's world vertices.
fn connectivity(floes: &StaticFloes, keep: impl Fn(usize) -> bool) -> (Vec<i64>, usize) {
    let (mut out, mut cells) = (Vec::new(), 0);
    for i in (0..floes.len()).filter(|&i| keep(i)) {
        let (a, b) = (
            floes.vertex_offsets[i] as i64,
            floes.vertex_offsets[i + 1] as i64,
        );
        out.push(3);
        out.push(b - a);
        out.extend(a..b);
        cells += 1;
    }
    (out, cells)
}

/// Each floe's mean `theta` and `mu` over its contacts (NaN without one);
/// the contacts name floes below `n`.
fn contact_means(n: usize, c: &ContactSnapshot) -> [Vec<f64>; 2] {
    let (mut theta, mut mu, mut count) = (vec![0.0; n], vec![0.0; n], vec![0u32; n]);
    for (k, pair) in c.pair.iter().enumerate() {
        for &i in pair {
            let i = i as usize;
            theta[i] += c.theta[k];
            mu[i] += c.mu[k];
            count[i] += 1;
        }
    }
    for i in 0..n {
        let m = count[i] as f64;
        theta[i] = if count[i] > 0 { theta[i] / m } else { f64::NAN };
        mu[i] = if count[i] > 0 { mu[i] / m } else { f64::NAN };
    }
    [theta, mu]
}

/// Writes a sidecar dataset, shuffled and deflated (level 4, as the run
/// files) in chunks of at most 65,536 rows.
fn put<T: hdf5::H5Type>(
    side: &hdf5::File,
    sidecar: &Path,
    path: &str,
    data: &[T],
    shape: &[usize],
) -> Result<(), IoError> {
    let mut b = side.new_dataset::<T>();
    if shape[0] > 0 {
        let mut chunk = shape.to_vec();
        chunk[0] = chunk[0].min(layout::MAX_FLOE_CHUNK);
        b = b.chunk(&chunk[..]).shuffle().deflate(4);
    }
    b.shape(shape)
        .create(path)
        .and_then(|d| d.write_raw(data))
        .at(sidecar, || format!("writing /{path}"))
}

/// Each contact's two ends: floe `a`'s centroid and floe `b`'s image
/// nearest to it (across a periodic seam, the image beside `a`).
fn contact_ends(position: &[[f64; 2]], pair: &[[u32; 2]], period: [Option<f64>; 2]) -> Vec<f64> {
    let mut out = Vec::with_capacity(4 * pair.len());
    for &[a, b] in pair {
        let (pa, mut pb) = (position[a as usize], position[b as usize]);
        for axis in 0..2 {
            if let Some(l) = period[axis] {
                pb[axis] += l * ((pa[axis] - pb[axis]) / l).round();
            }
        }
        out.extend([pa[0], pa[1], pb[0], pb[1]]);
    }
    out
}

/// The XDMF text; the sidecar written to `sidecar_part`.
fn describe(
    file: &RunFile,
    run: &Path,
    xdmf: &Path,
    sidecar: &Path,
    sidecar_part: &Path,
) -> Result<(String, usize), IoError> {
    let n_snapshots = file.snapshot_count()?;
    let side = h5::create_file(sidecar_part).at(sidecar, || "creating the sidecar".into())?;
    let (run_ref, side_ref) = (
        escape(&reference(run, xdmf)),
        escape(&reference(sidecar, xdmf)),
    );
    let write = |path: &str, data: &[f64], shape: &[usize]| put(&side, sidecar, path, data, shape);
    let (mut floes_xml, mut walls_xml, mut contacts_xml) =
        (String::new(), String::new(), String::new());
    let domain = file.metadata()?.domain;
    let period = [0, 1].map(|a| domain.periodic[a].then_some(domain.size_m[a]));
    // Each snapshot's contact rows; the contacts' connectivity, shared by
    // every snapshot: line k joins points 2k and 2k + 1.
    let contact_rows = (0..n_snapshots)
        .map(|k| file.contact_rows(k))
        .collect::<Result<Vec<_>, _>>()?;
    let most_contacts = contact_rows.iter().map(|r| r.1).max().unwrap_or(0);
    let lines: Vec<i64> = (0..2 * most_contacts as i64).collect();
    put(&side, sidecar, "lines", &lines, &[most_contacts, 2])?;
    let contact_shape = |name: &str| -> Result<Vec<usize>, IoError> {
        Ok(file.ds(&format!("{}/{name}", layout::CONTACTS))?.shape())
    };
    let contact_shapes = layout::CONTACT_FIELDS
        .iter()
        .filter(|f| f.2 == 1)
        .map(|f| Ok((f.0, contact_shape(f.0)?)))
        .collect::<Result<Vec<_>, IoError>>()?;
    // Per floe set: its cell counts and connectivity lengths, and the
    // shapes of its snapshot elements.
    let mut segment_done = None;
    let mut cells = (0, 0, 0, 0);
    let mut shapes: Vec<(&str, Vec<usize>)> = Vec::new();
    for (k, &(start, count)) in contact_rows.iter().enumerate() {
        let (segment, row) = file.locate(k)?;
        let floes = file.floes_at(k)?;
        let snap = file.snapshot(k)?;
        let contacts = file.contacts(k)?;
        let n = floes.len();
        let group = layout::floe_segment(segment);
        if let Some(bad) = contacts.pair.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(invalid(
                run,
                format!(
                    "snapshot {k}: a contact names floe {bad}, past its {n} floes (file damaged)"
                ),
            ));
        }
        if segment_done != Some(segment) {
            let (all, all_cells) = connectivity(&floes, |_| true);
            let (walls, wall_cells) = connectivity(&floes, |i| floes.prescribed[i]);
            for (name, data) in [("floes", &all), ("walls", &walls)] {
                let path = format!("segments/{segment}/{name}");
                put(&side, sidecar, &path, data, &[data.len()])?;
            }
            cells = (all_cells, wall_cells, all.len(), walls.len());
            let stress = file.has_floe_stress().then_some(layout::FLOE_STRESS.0);
            shapes = ["velocity", "angular_velocity"]
                .into_iter()
                .chain(stress)
                .map(|name| Ok((name, file.ds(&format!("{group}/{name}/value"))?.shape())))
                .collect::<Result<_, IoError>>()?;
            segment_done = Some(segment);
        }
        let world: Vec<f64> = (0..n)
            .flat_map(|i| snap.world_vertices(&floes, i))
            .flatten()
            .collect();
        let v = world.len() / 2;
        write(&format!("snapshots/{k}/vertices"), &world, &[v, 2])?;
        let [theta, mu] = contact_means(n, &contacts);
        write(&format!("snapshots/{k}/mean_theta"), &theta, &[n])?;
        write(&format!("snapshots/{k}/mean_mu"), &mu, &[n])?;

        let time = snap.time_s;
        let geometry = format!(
            r#"<Geometry GeometryType="XY">{}</Geometry>"#,
            whole(
                &side_ref,
                &format!("snapshots/{k}/vertices"),
                Number::F64,
                &[v, 2]
            )
        );
        let topology = |name: &str, count: usize, len: usize| {
            format!(
                r#"<Topology TopologyType="Mixed" NumberOfElements="{count}">{}</Topology>"#,
                whole(
                    &side_ref,
                    &format!("segments/{segment}/{name}"),
                    Number::I64,
                    &[len]
                )
            )
        };
        let mut fields = String::new();
        for (name, shape) in &shapes {
            let kind = match shape.len() {
                2 => "Scalar",
                _ if *name == "velocity" => "Vector",
                _ => "Matrix",
            };
            let path = format!("{group}/{name}/value");
            fields += &attribute(name, kind, &snapshot_row(&run_ref, &path, shape, row));
        }
        for (name, number) in [
            ("thickness", Number::F64),
            ("mass", Number::F64),
            ("area", Number::F64),
            ("id", Number::U64),
            ("prescribed", Number::U8),
        ] {
            fields += &attribute(
                name,
                "Scalar",
                &whole(&run_ref, &format!("{group}/{name}"), number, &[n]),
            );
        }
        if file.has_land_marks(segment) {
            fields += &attribute(
                "land",
                "Scalar",
                &whole(
                    &run_ref,
                    &format!("{group}/{}", layout::LAND),
                    Number::U8,
                    &[n],
                ),
            );
        }
        for name in ["mean_theta", "mean_mu"] {
            fields += &attribute(
                name,
                "Scalar",
                &whole(
                    &side_ref,
                    &format!("snapshots/{k}/{name}"),
                    Number::F64,
                    &[n],
                ),
            );
        }
        let _ = write!(
            floes_xml,
            r#"<Grid Name="floes {k}" GridType="Uniform"><Time Value="{time:e}"/>{}{geometry}{fields}</Grid>"#,
            topology("floes", cells.0, cells.2)
        );
        // ParaView's reader cannot take an empty grid: a snapshot without
        // walls or contacts has none in that collection.
        if cells.1 > 0 {
            let _ = write!(
                walls_xml,
                r#"<Grid Name="walls {k}" GridType="Uniform"><Time Value="{time:e}"/>{}{geometry}</Grid>"#,
                topology("walls", cells.1, cells.3)
            );
        }

        // Contacts: lines from floe a's centroid to floe b's nearest image
        // (the sidecar's), their fields rows start..start+count of the file's.
        let ends = contact_ends(&snap.position, &contacts.pair, period);
        write(
            &format!("snapshots/{k}/contact_ends"),
            &ends,
            &[2 * count, 2],
        )?;
        let mut contact_fields = String::new();
        for (name, shape) in &contact_shapes {
            let path = format!("{}/{name}", layout::CONTACTS);
            contact_fields += &attribute(
                name,
                "Scalar",
                &rows(&run_ref, &path, Number::F64, shape, start, count),
            );
        }
        if count == 0 {
            continue;
        }
        let _ = write!(
            contacts_xml,
            r#"<Grid Name="contacts {k}" GridType="Uniform"><Time Value="{time:e}"/><Topology TopologyType="Polyline" NodesPerElement="2" NumberOfElements="{count}">{}</Topology><Geometry GeometryType="XY">{}</Geometry>{contact_fields}</Grid>"#,
            rows(
                &side_ref,
                "lines",
                Number::I64,
                &[most_contacts, 2],
                0,
                count
            ),
            whole(
                &side_ref,
                &format!("snapshots/{k}/contact_ends"),
                Number::F64,
                &[2 * count, 2]
            ),
        );
    }
    side.close().at(sidecar, || "closing".into())?;
    let collection = |name: &str, grids: &str| {
        format!(
            r#"<Grid Name="{name}" GridType="Collection" CollectionType="Temporal">{grids}</Grid>"#
        )
    };
    let text = format!(
        "<?xml version=\"1.0\" ?>\n<!-- A floe run for ParaView, written by floe export: the fields point into the run file, the polygons in world coordinates are in the sidecar. -->\n<Xdmf Version=\"3.0\"><Domain>{}{}{}</Domain></Xdmf>\n",
        collection("floes", &floes_xml),
        collection("walls", &walls_xml),
        collection("contacts", &contacts_xml),
    );
    Ok((text, n_snapshots))
}
