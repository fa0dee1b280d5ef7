//! Spot-light cookies: small greyscale images, generated here so they are reproducible from code.

use crate::components::Cookie;

/// Side of every cookie image in texels.
pub const COOKIE_SIZE: u32 = 64;

/// The cookie's image, `size` x `size` bytes (one channel, 255 = full light), rows top to bottom.
///
/// Texel (x, y) is what the light throws at the point its shadow map sees at the same uv.
pub fn cookie_image(cookie: Cookie, size: u32) -> Vec<u8> {
    let n = size.max(1);
    let mut pixels = Vec::with_capacity((n * n) as usize);
    for y in 0..n {
        for x in 0..n {
            let (u, v) = ((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
            let light = match cookie {
                Cookie::Window => window(u, v),
                Cookie::Leaves => leaves(u, v),
            };
            pixels.push((light.clamp(0.0, 1.0) * 255.0).round() as u8);
        }
    }
    pixels
}

/// Half width of the window's bars and frame, in uv.
pub const WINDOW_BAR: f32 = 0.04;

/// Four bright panes inside a dark frame, split by a dark cross through the middle.
fn window(u: f32, v: f32) -> f32 {
    let frame = 0.12;
    let on_frame = u < frame || u > 1.0 - frame || v < frame || v > 1.0 - frame;
    let on_cross = (u - 0.5).abs() < WINDOW_BAR || (v - 0.5).abs() < WINDOW_BAR;
    if on_frame || on_cross { 0.0 } else { 1.0 }
}

/// Soft spots of light on a dim ground, placed by the golden angle so none overlap much.
fn leaves(u: f32, v: f32) -> f32 {
    let mut light: f32 = 0.15;
    for i in 0..24 {
        let r = 0.42 * ((i as f32 + 0.5) / 24.0).sqrt();
        let a = i as f32 * 2.399_963;
        let (cu, cv) = (0.5 + r * a.cos(), 0.5 + r * a.sin());
        let d = ((u - cu).powi(2) + (v - cv).powi(2)).sqrt() / (0.045 + 0.02 * (i % 3) as f32);
        light = light.max(1.0 - d * d);
    }
    light
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(img: &[u8], size: u32, u: f32, v: f32) -> u8 {
        img[((v * size as f32) as u32 * size + (u * size as f32) as u32) as usize]
    }

    #[test]
    fn the_window_has_dark_bars_and_bright_panes() {
        let img = cookie_image(Cookie::Window, 64);
        assert_eq!(img.len(), 64 * 64);
        assert_eq!(at(&img, 64, 0.5, 0.3), 0, "vertical bar");
        assert_eq!(at(&img, 64, 0.3, 0.5), 0, "horizontal bar");
        assert_eq!(at(&img, 64, 0.02, 0.3), 0, "frame");
        for (u, v) in [(0.3, 0.3), (0.7, 0.3), (0.3, 0.7), (0.7, 0.7)] {
            assert_eq!(at(&img, 64, u, v), 255, "pane at {u}, {v}");
        }
    }

    #[test]
    fn leaves_are_dappled() {
        let img = cookie_image(Cookie::Leaves, COOKIE_SIZE);
        let bright = img.iter().filter(|p| **p > 200).count();
        let dim = img.iter().filter(|p| **p < 60).count();
        assert!(bright > img.len() / 50 && dim > img.len() / 4, "bright {bright}, dim {dim}");
    }
}
