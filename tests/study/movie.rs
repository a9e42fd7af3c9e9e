//! `floe render --movie` (floe_study::render::render_movie): a run's maps
//! as an animated GIF that the `gif` crate decodes (one frame per
//! snapshot chosen, each the size of the PNG maps, shown for 1/fps s,
//! looping), and as an H.264 MP4 whose frames ffprobe counts where ffmpeg
//! is installed (skipped with a note elsewhere). A movie is not replaced
//! without `force`, and no partial file is left behind.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::inherited_locks;
use crate::study_support;
use floe_io::RunFile;
use floe_study::render::movie::{self, Encoding, MovieArgs};
use floe_study::render::{render, render_movie, ColourBy, Snapshots};
use study_support::run_text;

/// Six floes drifting in a walled channel: a few snapshots.
const BOX: &str = r#"title = "drifting floes between walls"
duration_s = 6000.0
seed = 2

[domain]
size_m = [4000.0, 3000.0]
periodic = [true, false]

[tessellation]
kind = "grid"
columns = 3
rows = 2
gap_m = 300.0

[ice]
thickness_range_m = [0.5, 2.0]
initial_velocity_m_per_s = [0.3, 0.05]

[wind]
velocity_m_per_s = [8.0, 3.0]

[[wall]]
side = "bottom"

[[wall]]
side = "top"

[output]
snapshot_every_s = 1000.0
"#;

fn box_run(dir: &Path) -> PathBuf {
    run_text(dir, "box", BOX).unwrap()
}

/// Width and height of a PNG (its IHDR chunk).
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

/// Frames, their delay (hundredths of a second) and the size of a GIF.
fn decode_gif(path: &Path) -> (usize, Vec<u16>, (u32, u32), gif::Repeat) {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(File::open(path).unwrap()).unwrap();
    let size = (u32::from(decoder.width()), u32::from(decoder.height()));
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!(
            (u32::from(frame.width), u32::from(frame.height)),
            size,
            "every frame covers the whole picture"
        );
        // Decoded to RGBA: every pixel opaque.
        assert!(frame.buffer.chunks_exact(4).all(|p| p[3] == 255));
        delays.push(frame.delay);
    }
    (delays.len(), delays, size, decoder.repeat())
}

fn no_partial_files(dir: &Path) {
    let partial: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".partial"))
        .collect();
    assert!(partial.is_empty(), "{partial:?}");
}

#[test]
fn a_gif_of_the_chosen_snapshots_decodes_to_frames_of_the_maps_size() {
    let _programs = inherited_locks::starting_programs();
    let dir = tempfile::tempdir().unwrap();
    let h5 = box_run(dir.path());
    let n = RunFile::open(&h5).unwrap().snapshot_count().unwrap();
    assert!(n >= 7, "{n} snapshots");
    let gif_path = dir.path().join("box.gif");
    let args = MovieArgs {
        path: gif_path.clone(),
        fps: 5.0,
        force: false,
    };
    let mut calls = Vec::new();
    let written = render_movie(
        &h5,
        Snapshots::Every(1),
        ColourBy::Speed,
        &args,
        &mut |done, total| calls.push((done, total)),
    )
    .unwrap();
    assert_eq!(written.path, gif_path);
    assert_eq!(written.encoding, Encoding::Gif);
    assert_eq!(written.frames, n);
    assert_eq!(calls, (1..=n).map(|k| (k, n)).collect::<Vec<_>>());
    // The PNG maps of the same run are the frames' size.
    let pngs = render(
        &h5,
        Snapshots::One(0),
        ColourBy::Speed,
        &dir.path().join("maps"),
        false,
    )
    .unwrap();
    let size = png_size(&pngs[0]);
    assert_eq!(written.size, size);
    let (frames, delays, gif_size, repeat) = decode_gif(&gif_path);
    assert_eq!(frames, n);
    assert_eq!(gif_size, size);
    assert!(delays.iter().all(|&d| d == 20), "5 fps: {delays:?}");
    assert_eq!(repeat, gif::Repeat::Infinite);

    // Not replaced without force; replaced with it, by every other
    // snapshot coloured by pressure.
    let again = render_movie(
        &h5,
        Snapshots::One(-1),
        ColourBy::Speed,
        &args,
        &mut |_, _| {},
    );
    let e = again.unwrap_err();
    assert_eq!(e.exit_code(), 2, "{e}");
    assert_eq!(decode_gif(&gif_path).0, n, "the movie is untouched");
    let forced = MovieArgs {
        force: true,
        fps: 25.0,
        ..args.clone()
    };
    let written = render_movie(
        &h5,
        Snapshots::Every(2),
        ColourBy::Stress,
        &forced,
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(written.frames, n.div_ceil(2));
    let (frames, delays, _, _) = decode_gif(&gif_path);
    assert_eq!(frames, n.div_ceil(2));
    assert!(delays.iter().all(|&d| d == 4), "25 fps: {delays:?}");

    // Bad requests are bad input, and leave nothing.
    for (path, fps, what) in [
        ("box.avi", 10.0, ".avi"),
        ("b.gif", 0.0, "--fps"),
        ("b.gif", f64::NAN, "--fps"),
        ("b.gif", 500.0, "--fps"),
        ("box.h5", 10.0, ".h5"),
    ] {
        let bad = MovieArgs {
            path: dir.path().join(path),
            fps,
            force: true,
        };
        let e = render_movie(
            &h5,
            Snapshots::Every(1),
            ColourBy::Speed,
            &bad,
            &mut |_, _| {},
        )
        .unwrap_err();
        assert_eq!(e.exit_code(), 2, "{e}");
        assert!(e.to_string().contains(what), "{e}");
    }
    assert!(!dir.path().join("b.gif").exists());
    let e = render_movie(
        &h5,
        Snapshots::One(n as i64),
        ColourBy::Speed,
        &MovieArgs {
            path: dir.path().join("b.gif"),
            fps: 10.0,
            force: false,
        },
        &mut |_, _| {},
    )
    .unwrap_err();
    assert!(e.to_string().contains(&format!("--snapshot {n}")), "{e}");
    assert!(!dir.path().join("b.gif").exists());
    no_partial_files(dir.path());
}

/// The frames of an MP4, its codec, pixel format and size, by ffprobe.
fn probe(path: &Path) -> Option<(usize, String, String, u32, u32)> {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=nb_read_frames,codec_name,pix_fmt,width,height",
            "-of",
            "default=noprint_wrappers=1",
        ])
        .arg(path)
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let field = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(&format!("{key}=")))
            .unwrap_or_default()
            .to_string()
    };
    Some((
        field("nb_read_frames").parse().ok()?,
        field("codec_name"),
        field("pix_fmt"),
        field("width").parse().ok()?,
        field("height").parse().ok()?,
    ))
}

#[test]
fn an_mp4_through_ffmpeg_has_a_frame_per_snapshot() {
    let _programs = inherited_locks::starting_programs();
    let ffprobe = Command::new("ffprobe").arg("-version").output();
    if !movie::ffmpeg_available() || !ffprobe.is_ok_and(|o| o.status.success()) {
        eprintln!("skipped: ffmpeg or ffprobe is not on PATH (the GIF test covers the frames)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let h5 = box_run(dir.path());
    let n = RunFile::open(&h5).unwrap().snapshot_count().unwrap();
    // No extension: MP4, as ffmpeg is there.
    let written = render_movie(
        &h5,
        Snapshots::Every(1),
        ColourBy::Theta,
        &MovieArgs {
            path: dir.path().join("box"),
            fps: 12.0,
            force: false,
        },
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(written.encoding, Encoding::Mp4);
    assert_eq!(written.path, dir.path().join("box.mp4"));
    let (frames, codec, pix_fmt, w, h) = probe(&written.path).expect("ffprobe reads the movie");
    assert_eq!(frames, n);
    assert_eq!((codec.as_str(), pix_fmt.as_str()), ("h264", "yuv420p"));
    assert_eq!((w, h), written.size);
    assert!(w % 2 == 0 && h % 2 == 0);
    no_partial_files(dir.path());
}
