//! Prints the law registry's parameter tables as Markdown, the text
//! docs/scenarios.md holds between its law-table markers (a test in
//! tests/scenario/files.rs keeps the two equal):
//! `cargo run -p floe-friction --example law_tables`.

fn main() {
    print!("{}", floe_friction::LawRegistry::builtin().markdown());
}
