//! Palettes for GIF frames: at most 256 colours for a frame of RGB
//! pixels, and each pixel's index into them.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A palette of at most 256 colours (RGB) for the RGB pixels `rgb`, and
/// each pixel's index into it: the frame's own colours if there are at
/// most 256, else 256 that NeuQuant learns from its distinct colours, each
/// weighted by the square root of its pixel count (rare colours, the
/// edges of floes and text, still count; measured on the demo's frames:
/// 0.9 of 255 mean error per pixel, 16 at the 99.9th percentile).
pub(crate) fn quantise(rgb: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let pixels = || rgb.chunks_exact(3).map(|p| pack([p[0], p[1], p[2]]));
    // Pixel counts of the distinct colours; runs of one colour are common.
    let mut counts: ColourMap<usize> = ColourMap::default();
    let mut run: Option<(u32, usize)> = None;
    for c in pixels() {
        match &mut run {
            Some((colour, n)) if *colour == c => *n += 1,
            _ => {
                if let Some((colour, n)) = run {
                    *counts.entry(colour).or_default() += n;
                }
                run = Some((c, 1));
            }
        }
    }
    if let Some((colour, n)) = run {
        *counts.entry(colour).or_default() += n;
    }
    let mut distinct: Vec<(u32, usize)> = counts.into_iter().collect();
    distinct.sort_unstable();
    if distinct.len() <= 256 {
        let palette: Vec<u8> = distinct.iter().flat_map(|&(c, _)| unpack(c)).collect();
        let index = distinct
            .iter()
            .enumerate()
            .map(|(i, &(c, _))| (c, i as u8))
            .collect();
        return (palette, indices(pixels(), &index));
    }
    let mut samples = Vec::new();
    for &(c, n) in &distinct {
        let [r, g, b] = unpack(c);
        for _ in 0..((n as f64).sqrt() as usize).max(1) {
            samples.extend_from_slice(&[r, g, b, 255]);
        }
    }
    let quant = color_quant::NeuQuant::new(1, 256, &samples);
    let index = distinct
        .iter()
        .map(|&(c, _)| {
            let [r, g, b] = unpack(c);
            (c, quant.index_of(&[r, g, b, 255]) as u8)
        })
        .collect();
    (quant.color_map_rgb(), indices(pixels(), &index))
}

/// Each pixel's palette index.
fn indices(pixels: impl Iterator<Item = u32>, index: &ColourMap<u8>) -> Vec<u8> {
    let mut last: Option<(u32, u8)> = None;
    pixels
        .map(|c| match last {
            Some((colour, i)) if colour == c => i,
            _ => {
                let i = index.get(&c).copied().unwrap_or(0);
                last = Some((c, i));
                i
            }
        })
        .collect()
}

fn pack([r, g, b]: [u8; 3]) -> u32 {
    u32::from(r) << 16 | u32::from(g) << 8 | u32::from(b)
}

fn unpack(c: u32) -> [u8; 3] {
    [(c >> 16) as u8, (c >> 8) as u8, c as u8]
}

/// A map keyed by packed colours, with a multiplicative hash (the default
/// SipHash costs more than the rest of the quantisation).
type ColourMap<V> = HashMap<u32, V, BuildHasherDefault<ColourHasher>>;

/// Fibonacci hashing of a packed colour.
#[derive(Default)]
struct ColourHasher(u64);

impl Hasher for ColourHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 << 8 | u64::from(b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }

    fn write_u32(&mut self, c: u32) {
        self.0 = u64::from(c).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }

    fn finish(&self) -> u64 {
        self.0.rotate_left(26)
    }
}

#[cfg(test)]
mod tests {
    use super::quantise;

    #[test]
    fn few_colours_are_kept_exactly_and_many_are_mapped_to_256() {
        let rgb: Vec<u8> = (0..1000u32)
            .flat_map(|i| [(i % 7) as u8 * 30, 10, 200])
            .collect();
        let (palette, indices) = quantise(&rgb);
        assert_eq!(palette.len(), 7 * 3);
        for (p, &i) in rgb.chunks_exact(3).zip(&indices) {
            assert_eq!(p, &palette[3 * i as usize..3 * i as usize + 3]);
        }
        let rgb: Vec<u8> = (0..100_000u32)
            .flat_map(|i| [(i % 251) as u8, (i / 251 % 256) as u8, 7])
            .collect();
        let (palette, indices) = quantise(&rgb);
        assert_eq!(palette.len(), 256 * 3);
        assert_eq!(indices.len(), 100_000);
        // Each pixel gets a near colour.
        let worst = rgb
            .chunks_exact(3)
            .zip(&indices)
            .map(|(p, &i)| {
                (0..3)
                    .map(|c| (p[c] as i32 - palette[3 * i as usize + c] as i32).abs())
                    .max()
                    .unwrap_or(0)
            })
            .max()
            .unwrap_or(0);
        assert!(worst < 40, "{worst}");
    }
}
