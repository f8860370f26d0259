//! The simulated time written onto a screenshot, in a small built-in bitmap font, and read
//! back (so a test, or a tool sorting screenshots, can tell the time from the pixels alone).
//!
//! The stamp is white text on a black box in the image's bottom-left corner: `t = 1.234 s`.

use image::{Rgba, RgbaImage};

/// Pixels per font pixel.
const SCALE: u32 = 3;
/// Font cell: 5 columns by 7 rows, plus one column of spacing.
const COLUMNS: u32 = 5;
const ROWS: u32 = 7;
const ADVANCE: u32 = (COLUMNS + 1) * SCALE;
/// Margin between the image's edge and the box, and between the box and the text.
const MARGIN: u32 = 8;
const PADDING: u32 = 6;

/// 5x7 glyphs, one byte a row, the low 5 bits left to right.
const GLYPHS: &[(char, [u8; 7])] = &[
    ('0', [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E]),
    ('1', [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E]),
    ('2', [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F]),
    ('3', [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E]),
    ('4', [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02]),
    ('5', [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E]),
    ('6', [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E]),
    ('7', [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08]),
    ('8', [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E]),
    ('9', [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C]),
    ('.', [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C]),
    ('-', [0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00]),
    ('=', [0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00]),
    ('t', [0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06]),
    ('s', [0x00, 0x00, 0x0E, 0x10, 0x0E, 0x01, 0x1E]),
    (' ', [0x00; 7]),
];

fn glyph(c: char) -> [u8; 7] {
    GLYPHS
        .iter()
        .find(|(g, _)| *g == c)
        .map_or([0x1F; 7], |(_, rows)| *rows)
}

/// The text of a stamp: `t = 1.234 s` (milliseconds, rounded).
pub fn time_text(time: f64) -> String {
    format!("t = {time:.3} s")
}

/// The most characters a stamp holds (a time up to 10^9 s).
const MAX_CHARS: u32 = 20;

fn text_origin(image: &RgbaImage) -> Option<(u32, u32)> {
    let height = ROWS * SCALE + 2 * PADDING + MARGIN;
    let y = image.height().checked_sub(height)? + PADDING;
    Some((MARGIN + PADDING, y))
}

/// Writes [`time_text`] onto the bottom-left corner of `image`, on a black box. Images too
/// small to hold it are left as they are.
pub fn stamp_time(image: &mut RgbaImage, time: f64) {
    let text = time_text(time);
    let Some((x0, y0)) = text_origin(image) else {
        return;
    };
    let width = text.chars().count() as u32 * ADVANCE + 2 * PADDING;
    if MARGIN + width > image.width() {
        return;
    }
    let black = Rgba([0, 0, 0, 255]);
    let white = Rgba([255, 255, 255, 255]);
    for y in y0 - PADDING..y0 + ROWS * SCALE + PADDING {
        for x in MARGIN..MARGIN + width {
            image.put_pixel(x, y, black);
        }
    }
    for (i, c) in text.chars().enumerate() {
        let rows = glyph(c);
        for (row, bits) in rows.iter().enumerate() {
            for col in 0..COLUMNS {
                if bits >> (COLUMNS - 1 - col) & 1 == 1 {
                    let x = x0 + i as u32 * ADVANCE + col * SCALE;
                    let y = y0 + row as u32 * SCALE;
                    for dy in 0..SCALE {
                        for dx in 0..SCALE {
                            image.put_pixel(x + dx, y + dy, white);
                        }
                    }
                }
            }
        }
    }
}

/// Reads back the time that [`stamp_time`] wrote, or `None` if the image has no stamp.
pub fn read_time_stamp(image: &RgbaImage) -> Option<f64> {
    let (x0, y0) = text_origin(image)?;
    let mut text = String::new();
    for i in 0..MAX_CHARS {
        let x = x0 + i * ADVANCE;
        if x + COLUMNS * SCALE > image.width() {
            break;
        }
        let mut rows = [0u8; 7];
        for (row, bits) in rows.iter_mut().enumerate() {
            for col in 0..COLUMNS {
                let p = image.get_pixel(x + col * SCALE + SCALE / 2, y0 + row as u32 * SCALE + 1);
                let lit = p.0[..3].iter().all(|&c| c > 200);
                let dark = p.0[..3].iter().all(|&c| c < 55);
                if !lit && !dark {
                    return None;
                }
                *bits |= u8::from(lit) << (COLUMNS - 1 - col);
            }
        }
        let c = GLYPHS.iter().find(|(_, g)| *g == rows)?.0;
        text.push(c);
        if text.ends_with(" s") {
            break;
        }
    }
    text.strip_prefix("t = ")?.strip_suffix(" s")?.parse().ok()
}
