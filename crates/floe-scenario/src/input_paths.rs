//! Scenario text whose relative input paths (every `file = "..."` key:
//! forcing, coastlines, ice grids) are made absolute, for copies of a
//! scenario run from elsewhere (the variants `floe compare`, `floe sweep`
//! and `floe rheology` write beside their results).

use std::path::Path;

use toml_edit::{DocumentMut, Item, Table, TableLike, Value};

/// The key naming an input file in any table.
const FILE_KEY: &str = "file";

/// `text` with each relative `file` value joined to `base_dir` (made
/// absolute). Text that does not parse is returned unchanged (the
/// scenario reader reports it).
pub fn anchor_input_paths(text: &str, base_dir: &Path) -> String {
    let Ok(mut doc) = text.parse::<DocumentMut>() else {
        return text.to_string();
    };
    let base = std::path::absolute(base_dir).unwrap_or_else(|_| base_dir.to_path_buf());
    anchor_table(doc.as_table_mut(), &base);
    doc.to_string()
}

fn anchor_table(t: &mut Table, base: &Path) {
    for (key, item) in t.iter_mut() {
        anchor_item(key.get(), item, base);
    }
}

fn anchor_like(t: &mut dyn TableLike, base: &Path) {
    for (key, item) in t.iter_mut() {
        anchor_item(key.get(), item, base);
    }
}

fn anchor_item(key: &str, item: &mut Item, base: &Path) {
    match item {
        Item::Table(t) => anchor_table(t, base),
        Item::ArrayOfTables(a) => a.iter_mut().for_each(|t| anchor_table(t, base)),
        Item::Value(v) => anchor_value(key, v, base),
        Item::None => {}
    }
}

fn anchor_value(key: &str, v: &mut Value, base: &Path) {
    match v {
        Value::String(s) if key == FILE_KEY => {
            let written = s.value().clone();
            if !Path::new(&written).is_absolute() {
                let decor = s.decor().clone();
                let mut new = toml_edit::Formatted::new(base.join(&written).display().to_string());
                *new.decor_mut() = decor;
                *s = new;
            }
        }
        Value::InlineTable(t) => anchor_like(t, base),
        Value::Array(a) => a.iter_mut().for_each(|x| anchor_value("", x, base)),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::anchor_input_paths;
    use std::path::Path;

    #[test]
    fn relative_files_become_absolute_and_nothing_else_moves() {
        let text = "# a storm\nduration_s = 10\n[wind]\nfile = \"forcing/w.nc\" # ERA5\nvariables = [\"u10\", \"v10\"]\n\
                    [ocean]\nfile = \"/data/o.nc\"\nsea_surface_height = { variable = \"zos\", file = \"ssh.nc\" }\n\
                    [[land]]\nfile = \"coast.geojson\"\n";
        let out = anchor_input_paths(text, Path::new("/runs/nares"));
        assert!(
            out.contains("file = \"/runs/nares/forcing/w.nc\" # ERA5"),
            "{out}"
        );
        assert!(out.contains("file = \"/data/o.nc\""), "{out}");
        assert!(out.contains("file = \"/runs/nares/ssh.nc\""), "{out}");
        assert!(
            out.contains("file = \"/runs/nares/coast.geojson\""),
            "{out}"
        );
        assert!(out.starts_with("# a storm\nduration_s = 10\n"), "{out}");
        assert!(out.contains("variables = [\"u10\", \"v10\"]"), "{out}");
    }
}
