//! The ASPRS classes of LAS 1.4 (R15, table 17): their names, and the colours
//! they are shown in. The LAS specification names the classes but gives no
//! colours; these are the ones Potree shows them in, so a user switching over
//! sees the same picture.

use crate::cloud::Values;

/// The name of ASPRS class `class`.
pub fn name(class: u8) -> &'static str {
    match class {
        0 => "created, never classified",
        1 => "unclassified",
        2 => "ground",
        3 => "low vegetation",
        4 => "medium vegetation",
        5 => "high vegetation",
        6 => "building",
        7 => "low point (noise)",
        8 => "model key-point (reserved)",
        9 => "water",
        10 => "rail",
        11 => "road surface",
        12 => "overlap (reserved)",
        13 => "wire guard (shield)",
        14 => "wire conductor (phase)",
        15 => "transmission tower",
        16 => "wire-structure connector",
        17 => "bridge deck",
        18 => "high noise",
        19..=63 => "reserved",
        _ => "user definable",
    }
}

/// The sRGB colour class `class` is shown in.
pub fn colour(class: u8) -> [u8; 3] {
    match class {
        0 | 1 => [128, 128, 128],
        2 => [161, 82, 46],
        3 => [0, 255, 0],
        4 => [0, 204, 0],
        5 => [0, 153, 0],
        6 => [255, 168, 0],
        7 => [255, 0, 255],
        8 => [255, 0, 0],
        9 => [0, 0, 255],
        10 => [128, 77, 26],
        11 => [77, 77, 77],
        12 => [255, 255, 0],
        13 => [204, 204, 128],
        14 => [230, 230, 26],
        15 => [77, 26, 0],
        16 => [255, 230, 128],
        17 => [204, 128, 77],
        18 => [255, 0, 128],
        _ => [77, 153, 153],
    }
}

/// `(class, points)` for every class present in `values`, in class order.
pub fn counts(values: &Values) -> Vec<(u8, usize)> {
    let mut counts = [0usize; 256];
    for i in 0..values.len() {
        counts[(values.get(i) as usize).min(255)] += 1;
    }
    (0..=255u8).filter(|&c| counts[c as usize] > 0).map(|c| (c, counts[c as usize])).collect()
}
