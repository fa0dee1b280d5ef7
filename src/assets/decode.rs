//! PNG and JPEG images into 8-bit RGBA, with their size known (and refused if too large) before
//! the pixels are decoded: `png` reads PNG, `zune-jpeg` reads JPEG (baseline and progressive,
//! grey, RGB and CMYK), nothing else. Either refuses an image it cannot read whole: a JPEG is
//! decoded strictly, since a lenient decoder draws a file cut short as grey past the cut, and
//! scrambled before it, without a word.

use zune_jpeg::zune_core::{bytestream::ZCursor, colorspace::ColorSpace, options::DecoderOptions};

/// An image whose header has been read: its size, and how to decode its pixels.
pub enum Header<'a> {
    /// A PNG image, its header read.
    Png(Box<png::Reader<std::io::Cursor<&'a [u8]>>>),
    /// A JPEG image, its header read.
    Jpeg(Box<zune_jpeg::JpegDecoder<ZCursor<&'a [u8]>>>, (u32, u32)),
}

/// Reads the header of `bytes` if they are a PNG or JPEG of at most `max` texels a side.
pub fn header(bytes: &[u8], max: u32) -> Result<Header<'_>, String> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::normalize_to_color8());
        // The size is checked against the caller's budget, not the decoder's 64 MiB default.
        decoder.set_limits(png::Limits { bytes: usize::MAX });
        let reader = decoder.read_info().map_err(|e| format!("a broken PNG: {e}"))?;
        let (width, height) = (reader.info().width, reader.info().height);
        check_size(width, height, max)?;
        Ok(Header::Png(Box::new(reader)))
    } else if bytes.starts_with(&[0xff, 0xd8]) {
        let side = max as usize;
        let options = DecoderOptions::default()
            .set_max_width(side)
            .set_max_height(side)
            .jpeg_set_out_colorspace(ColorSpace::RGBA)
            .set_strict_mode(true);
        let mut decoder = zune_jpeg::JpegDecoder::new_with_options(ZCursor::new(bytes), options);
        decoder.decode_headers().map_err(|e| format!("a broken JPEG: {e:?}"))?;
        let info = decoder.info().ok_or("a broken JPEG: no frame header")?;
        let size = (u32::from(info.width), u32::from(info.height));
        check_size(size.0, size.1, max)?;
        Ok(Header::Jpeg(Box::new(decoder), size))
    } else {
        Err("it is neither PNG nor JPEG (umbra decodes those only)".into())
    }
}

fn check_size(width: u32, height: u32, max: u32) -> Result<(), String> {
    if width == 0 || height == 0 || width > max || height > max {
        return Err(format!("it is {width}x{height}; images are 1 to {max} texels a side"));
    }
    Ok(())
}

impl Header<'_> {
    /// Width and height in texels.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        match self {
            Header::Png(r) => (r.info().width, r.info().height),
            Header::Jpeg(_, size) => *size,
        }
    }

    /// The pixels as RGBA, 8 bits a channel, rows top to bottom.
    pub fn decode(self) -> Result<Vec<u8>, String> {
        match self {
            Header::Png(mut reader) => {
                let mut buf = vec![0; reader.output_buffer_size().ok_or("a PNG too large to decode")?];
                let frame = reader.next_frame(&mut buf).map_err(|e| format!("a broken PNG: {e}"))?;
                buf.truncate(frame.buffer_size());
                rgba(buf, frame.color_type)
            }
            Header::Jpeg(mut decoder, (width, height)) => {
                let pixels = decoder.decode().map_err(|e| format!("a broken JPEG, cut short or damaged: {e}"))?;
                let expected = width as usize * height as usize * 4;
                if pixels.len() != expected {
                    return Err(format!("a JPEG decoded to {} bytes, not {expected}", pixels.len()));
                }
                Ok(pixels)
            }
        }
    }
}

/// 8-bit pixels of `colour` as RGBA (indexed colour has been expanded by the decoder); RGBA
/// pixels are taken as they are, not copied.
fn rgba(pixels: Vec<u8>, colour: png::ColorType) -> Result<Vec<u8>, String> {
    Ok(match colour {
        png::ColorType::Rgba => pixels,
        png::ColorType::Rgb => pixels.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
        png::ColorType::GrayscaleAlpha => pixels.chunks_exact(2).flat_map(|p| [p[0], p[0], p[0], p[1]]).collect(),
        png::ColorType::Grayscale => pixels.iter().flat_map(|&g| [g, g, g, 255]).collect(),
        png::ColorType::Indexed => return Err("a PNG whose palette was not expanded".into()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32, colour: png::ColorType, depth: png::BitDepth, data: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, width, height);
        encoder.set_color(colour);
        encoder.set_depth(depth);
        if colour == png::ColorType::Indexed {
            encoder.set_palette(vec![10, 20, 30, 40, 50, 60]);
        }
        encoder.write_header().unwrap().write_image_data(data).unwrap();
        out
    }

    fn decoded(bytes: &[u8]) -> ((u32, u32), Vec<u8>) {
        let h = header(bytes, 64).unwrap();
        (h.size(), h.decode().unwrap())
    }

    #[test]
    fn every_png_colour_type_and_depth_becomes_rgba8() {
        use png::{BitDepth::*, ColorType::*};
        assert_eq!(decoded(&png(1, 1, Rgba, Eight, &[1, 2, 3, 4])), ((1, 1), vec![1, 2, 3, 4]));
        assert_eq!(decoded(&png(2, 1, Rgb, Eight, &[1, 2, 3, 4, 5, 6])).1, vec![1, 2, 3, 255, 4, 5, 6, 255]);
        assert_eq!(decoded(&png(1, 1, GrayscaleAlpha, Eight, &[7, 8])).1, vec![7, 7, 7, 8]);
        assert_eq!(decoded(&png(1, 1, Grayscale, Sixteen, &[0xab, 0xcd])).1, vec![0xab, 0xab, 0xab, 255]);
        // Two 1-bit texels of a two-colour palette.
        assert_eq!(decoded(&png(2, 1, Indexed, One, &[0b0100_0000])).1, vec![10, 20, 30, 255, 40, 50, 60, 255]);
    }

    #[test]
    fn jpegs_of_colour_and_grey_become_rgba8() {
        let (size, red) = decoded(include_bytes!("test_images/red.jpg"));
        assert_eq!(size, (4, 2));
        for p in red.chunks_exact(4) {
            assert!(p[0] > 240 && p[1] < 15 && p[2] < 15 && p[3] == 255, "{p:?} is not red");
        }
        let (size, grey) = decoded(include_bytes!("test_images/gray.jpg"));
        assert_eq!(size, (3, 1));
        for p in grey.chunks_exact(4) {
            assert!(p[0].abs_diff(128) < 4 && p[0] == p[1] && p[1] == p[2] && p[3] == 255, "{p:?} is not grey");
        }
    }

    fn refusal(bytes: &[u8], max: u32) -> String {
        header(bytes, max).err().expect("refused")
    }

    #[test]
    fn what_is_not_a_whole_png_or_jpeg_of_a_fitting_size_is_refused() {
        assert!(refusal(b"GIF89a....", 64).contains("neither PNG nor JPEG"));
        assert!(header(b"", 64).is_err());
        let big = png(65, 1, png::ColorType::Grayscale, png::BitDepth::Eight, &[0; 65]);
        assert!(refusal(&big, 64).contains("65x1"), "the size is refused before decoding");
        let jpeg = include_bytes!("test_images/red.jpg");
        assert!(header(jpeg, 3).is_err(), "a JPEG wider than the limit");
        let cut = png(4, 4, png::ColorType::Rgba, png::BitDepth::Eight, &[5; 64]);
        let half = &cut[..cut.len() / 2];
        assert!(header(half, 64).and_then(Header::decode).is_err(), "a PNG cut in half");
        assert!(header(&jpeg[..jpeg.len() / 2], 64).and_then(Header::decode).is_err(), "a JPEG cut in half");
        assert!(header(&jpeg[..4], 64).is_err(), "a JPEG with no header");
    }

    #[test]
    fn a_jpeg_cut_short_is_refused_as_cut() {
        let whole = include_bytes!("test_images/gradient.jpg");
        assert_eq!(decoded(whole).0, (64, 48));
        let progressive = include_bytes!("test_images/gradient-progressive.jpg");
        assert_eq!(decoded(progressive).0, (64, 48));
        for (name, jpeg) in [("baseline", &whole[..]), ("progressive", &progressive[..])] {
            // Its headers whole, its pixels cut: the size is known, the decoding refused.
            let cut = &jpeg[..jpeg.len() * 2 / 3];
            let header = header(cut, 64).unwrap();
            assert_eq!(header.size(), (64, 48), "{name}");
            let why = header.decode().expect_err(name);
            assert!(why.starts_with("a broken JPEG, cut short"), "{name}: {why}");
        }
    }
}
