//! The WGSL sources and how they are put together. A module is a list of files, each depending
//! only on the files before it, after a prelude of the constants Rust and WGSL share
//! ([`super::gpu_types::prelude`]); a line of the joined text can be traced back to its file.

/// One WGSL file of `shaders/`.
#[derive(Clone, Copy, Debug)]
pub struct ShaderFile {
    /// Its name in `shaders/`.
    pub name: &'static str,
    /// Its text.
    pub text: &'static str,
}

macro_rules! shader_file {
    ($name:literal) => {
        ShaderFile { name: $name, text: include_str!(concat!("../../shaders/", $name)) }
    };
}

/// The object uniform, the material texture, the vertex layout and the pipeline constants.
pub const COMMON: ShaderFile = shader_file!("common.wgsl");
/// Skinning by the joint palette.
pub const SKINNING: ShaderFile = shader_file!("skinning.wgsl");
/// The layer struct both passes read and the moments a moment map stores.
pub const MOMENTS: ShaderFile = shader_file!("moments.wgsl");
/// The separable blur of moment maps.
pub const BLUR: ShaderFile = shader_file!("blur.wgsl");
/// Moment maps resolved from depth and blurred in one compute dispatch.
pub const MOMENT_COMPUTE: ShaderFile = shader_file!("moment_compute.wgsl");
/// The shadow pass (depth, and moments where a light uses them).
pub const SHADOW: ShaderFile = shader_file!("shadow.wgsl");
/// The frame uniform, the lights and the layers (bind group 0 of the main pass).
pub const FRAME: ShaderFile = shader_file!("frame.wgsl");
/// Screen-space contact shadows: a march through the camera's depth.
pub const CONTACT: ShaderFile = shader_file!("contact.wgsl");
/// The shadow-map lookups, one function per method.
pub const SAMPLING: ShaderFile = shader_file!("shadow_sampling.wgsl");
/// PCSS: its blocker searches and the filter they size.
pub const PCSS: ShaderFile = shader_file!("pcss.wgsl");
/// The face of a point light's cube that holds a direction, for the lookups and the marking.
pub const CUBE: ShaderFile = shader_file!("cube.wgsl");
/// Virtual shadow maps: the layer a paged light's lookup reads.
pub const PAGES: ShaderFile = shader_file!("pages.wgsl");
/// The marking of the pages a paged light's visible pixels need.
pub const PAGE_MARKS: ShaderFile = shader_file!("page_marks.wgsl");
/// Every light kind seen from a surface point: reach, shadow test, cookie.
pub const LIGHTS: ShaderFile = shader_file!("lights.wgsl");
/// The main pass, the measuring view and the probes.
pub const MAIN: ShaderFile = shader_file!("main.wgsl");
/// Planar shadows drawn over the ground.
pub const PLANAR: ShaderFile = shader_file!("planar.wgsl");
/// Lines in the world over the picture (the light volumes).
pub const LINES: ShaderFile = shader_file!("lines.wgsl");
/// The shadow-map viewer's atlas.
pub const MAP_VIEW: ShaderFile = shader_file!("map_view.wgsl");
/// The bare depth pass the bench measures the shadow pass against.
pub const BARE_DEPTH: ShaderFile = shader_file!("bare_depth.wgsl");
/// The depth reduction of sample distribution shadow maps.
pub const SDSM: ShaderFile = shader_file!("sdsm.wgsl");
/// Filling an atlas tile before its casters: cleared, or its casters at rest put back.
pub const TILE: ShaderFile = shader_file!("tile.wgsl");

/// The shadow pass's files, in dependency order.
pub const SHADOW_MODULE: &[ShaderFile] = &[COMMON, SKINNING, MOMENTS, SHADOW];
/// The moment blur's and resolve's files.
pub const BLUR_MODULE: &[ShaderFile] = &[MOMENTS, BLUR];
/// The main pass's files, in dependency order.
pub const MAIN_MODULE: &[ShaderFile] =
    &[COMMON, SKINNING, MOMENTS, FRAME, SAMPLING, PCSS, CONTACT, CUBE, PAGES, LIGHTS, MAIN];
/// The planar shadows' files: the main pass's, and its own.
pub const PLANAR_MODULE: &[ShaderFile] =
    &[COMMON, SKINNING, MOMENTS, FRAME, SAMPLING, PCSS, CONTACT, CUBE, PAGES, LIGHTS, MAIN, PLANAR];
/// The marking of pages' files.
pub const MARK_MODULE: &[ShaderFile] = &[CUBE, PAGE_MARKS];

/// A module's text, and the line where each of its parts begins.
#[derive(Clone, Debug)]
pub struct Composed {
    /// The prelude and the files, joined.
    pub text: String,
    /// Each part's name and first line (1-based) in `text`.
    starts: Vec<(&'static str, usize)>,
}

impl Composed {
    /// The prelude followed by `files`.
    pub fn new(files: &[ShaderFile]) -> Composed {
        let prelude = Composed { text: String::new(), starts: Vec::new() }
            .then("prelude (src/render/gpu_types.rs)", &super::gpu_types::prelude());
        files.iter().fold(prelude, |composed, f| composed.then(f.name, f.text))
    }

    /// It followed by `part` (generated text, named `name` in errors).
    #[must_use]
    pub fn then(mut self, name: &'static str, part: &str) -> Composed {
        self.starts.push((name, self.text.lines().count() + 1));
        self.text.push_str(part);
        if !part.ends_with('\n') {
            self.text.push('\n');
        }
        self
    }

    /// The file and line (both as in the file itself, 1-based) of line `line` of the joined text.
    #[cfg(test)]
    pub fn locate(&self, line: usize) -> (&'static str, usize) {
        let (name, start) = self.starts.iter().rev().find(|(_, start)| *start <= line).copied().unwrap_or(("?", 1));
        (name, line + 1 - start)
    }

    /// The module on `device`, labelled with its files' names.
    pub fn module(&self, device: &wgpu::Device) -> wgpu::ShaderModule {
        let label: Vec<&str> = self.starts.iter().skip(1).map(|(name, _)| *name).collect();
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(&label.join(" + ")),
            source: wgpu::ShaderSource::Wgsl(self.text.clone().into()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::gpu_types;
    use super::*;
    use crate::components::ShadowMethod;
    use naga::valid::{Capabilities, ValidationFlags, Validator};

    /// Parses and validates `composed`; an error names the file and line it is in.
    fn check(composed: &Composed) -> Result<(naga::Module, naga::valid::ModuleInfo), String> {
        let at = |span: naga::Span| {
            let offset = span.to_range().map_or(0, |r| r.start);
            let line = composed.text[..offset.min(composed.text.len())].lines().count().max(1);
            let (file, line) = composed.locate(line);
            format!("{file}:{line}")
        };
        let module = naga::front::wgsl::parse_str(&composed.text).map_err(|e| {
            let span = e.labels().next().map_or(naga::Span::UNDEFINED, |(s, _)| s);
            format!("{}: {}", at(span), e.message())
        })?;
        let info = Validator::new(ValidationFlags::all(), Capabilities::default()).validate(&module).map_err(|e| {
            let span = e.spans().next().map_or(naga::Span::UNDEFINED, |(s, _)| *s);
            // The error and each of its causes: "function is invalid: expression 12 is ...".
            let mut text = e.as_inner().to_string();
            let mut cause = std::error::Error::source(e.as_inner());
            while let Some(c) = cause {
                text += &format!(": {c}");
                cause = c.source();
            }
            format!("{}: {text}", at(span))
        })?;
        Ok((module, info))
    }

    #[test]
    fn every_shader_variant_parses_and_validates_without_a_gpu() {
        for (name, files) in [("shadow", SHADOW_MODULE), ("main", MAIN_MODULE), ("planar", PLANAR_MODULE)] {
            let composed = Composed::new(files);
            let (module, info) = check(&composed).unwrap_or_else(|e| panic!("{name}: {e}"));
            // Every value the pipelines give the constants, in every combination.
            for textured in [0.0, 1.0] {
                for (mask, blend) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)] {
                    // No method, each alone, and all together.
                    let all = ShadowMethod::ALL.iter().fold(0u32, |m, &x| m | 1 << x as u32);
                    let sets = ShadowMethod::ALL.iter().map(|&m| 1u32 << m as u32).chain([0, all]);
                    for methods in sets {
                        let mut constants = naga::back::PipelineConstants::default();
                        constants.insert("TEXTURED".into(), textured);
                        constants.insert("ALPHA_MASK".into(), mask);
                        constants.insert("ALPHA_BLEND".into(), blend);
                        if name != "shadow" {
                            constants.insert("SHADOW_METHODS".into(), methods as f64);
                        }
                        naga::back::pipeline_constants::process_overrides(&module, &info, None, &constants)
                            .unwrap_or_else(|e| panic!("{name} with {constants:?}: {e}"));
                    }
                }
            }
        }
    }

    #[test]
    fn the_blur_and_the_lines_parse_and_validate() {
        check(&Composed::new(BLUR_MODULE)).unwrap();
        // The compute resolve, storing into every format it may, from the atlas or multisampled.
        use wgpu::TextureFormat as F;
        for format in [F::Rgba16Float, F::Rgba32Float, F::Rg16Float, F::Rg32Float] {
            for multisampled in [false, true] {
                let composed = super::super::moment_compute::module_text(format, multisampled).unwrap();
                check(&composed).unwrap_or_else(|e| panic!("{format:?} multisampled {multisampled}: {e}"));
            }
        }
        check(&Composed::new(&[LINES])).unwrap();
        check(&Composed::new(&[BARE_DEPTH])).unwrap();
        check(&Composed::new(&[TILE])).unwrap();
        check(&Composed::new(MARK_MODULE)).unwrap();
        let (module, _) = check(&Composed::new(&[MAP_VIEW])).unwrap();
        // The viewer's uniform holds three vectors for every layer it shows.
        let terms = module.global_variables.iter().find(|(_, g)| g.name.as_deref() == Some("view_layers")).unwrap().1;
        match module.types[terms.ty].inner {
            naga::TypeInner::Array { size: naga::ArraySize::Constant(n), .. } => {
                assert_eq!(n.get() as usize, 3 * gpu_types::MAX_LAYERS)
            }
            ref other => panic!("view_layers is {other:?}"),
        }
    }

    #[test]
    fn a_shader_error_names_its_file_and_line() {
        let broken = ShaderFile { name: "broken.wgsl", text: "fn ok() {}\n\nfn bad() -> f32 { return oops; }\n" };
        let err = check(&Composed::new(&[COMMON, broken])).unwrap_err();
        assert!(err.starts_with("broken.wgsl:3:"), "{err}");
    }

    /// Each member's name and offset, and the size, of struct `name` in `module`.
    fn wgsl_layout(module: &naga::Module, name: &str) -> (Vec<(String, usize)>, usize) {
        let ty = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).map(|(_, t)| t);
        match ty.map(|t| &t.inner) {
            Some(naga::TypeInner::Struct { members, span }) => (
                members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize)).collect(),
                *span as usize,
            ),
            _ => panic!("no struct {name} in the WGSL"),
        }
    }

    #[test]
    fn rust_and_wgsl_lay_out_every_shared_struct_alike() {
        let (module, _) = check(&Composed::new(MAIN_MODULE)).unwrap();
        type Layout = &'static [(&'static str, usize)];
        let shared: [(&str, Layout, usize); 4] = [
            ("Object", gpu_types::Object::FIELDS, size_of::<gpu_types::Object>()),
            ("Frame", gpu_types::Frame::FIELDS, size_of::<gpu_types::Frame>()),
            ("GpuLight", gpu_types::GpuLight::FIELDS, size_of::<gpu_types::GpuLight>()),
            ("GpuLayer", gpu_types::GpuLayer::FIELDS, size_of::<gpu_types::GpuLayer>()),
        ];
        let (blur, _) = check(&Composed::new(BLUR_MODULE)).unwrap();
        let blur_struct = ("Blur", gpu_types::Blur::FIELDS, size_of::<gpu_types::Blur>());
        let (shadow, _) = check(&Composed::new(SHADOW_MODULE)).unwrap();
        let shadow_layer = ("GpuLayer", gpu_types::GpuLayer::FIELDS, size_of::<gpu_types::GpuLayer>());
        let (planar, _) = check(&Composed::new(PLANAR_MODULE)).unwrap();
        let planar_struct = ("GpuPlanar", gpu_types::GpuPlanar::FIELDS, size_of::<gpu_types::GpuPlanar>());
        let (sdsm, _) = check(&Composed::new(&[SDSM])).unwrap();
        let reduce_struct = ("Reduce", gpu_types::Reduce::FIELDS, size_of::<gpu_types::Reduce>());
        let (tile, _) = check(&Composed::new(&[TILE])).unwrap();
        let fill_struct = ("Fill", gpu_types::Fill::FIELDS, size_of::<gpu_types::Fill>());
        let (marks, _) = check(&Composed::new(MARK_MODULE)).unwrap();
        let mark_view = ("MarkView", gpu_types::MarkView::FIELDS, size_of::<gpu_types::MarkView>());
        let mark_light = ("MarkLight", gpu_types::MarkLight::FIELDS, size_of::<gpu_types::MarkLight>());
        let each = shared.iter().map(|s| (&module, *s)).chain([
            (&sdsm, reduce_struct),
            (&tile, fill_struct),
            (&marks, mark_view),
            (&marks, mark_light),
            (&blur, blur_struct),
            (&shadow, shadow_layer),
            (&planar, planar_struct),
        ]);
        for (module, (name, fields, size)) in each {
            let (wgsl, span) = wgsl_layout(module, name);
            let rust: Vec<(String, usize)> = fields.iter().map(|(f, o)| (f.to_string(), *o)).collect();
            assert_eq!(rust, wgsl, "{name}: Rust fields and offsets against the WGSL's");
            assert_eq!(size, span, "{name}: size");
        }
    }

    #[test]
    fn lines_are_traced_to_their_files() {
        let composed = Composed::new(&[COMMON, SKINNING]);
        let prelude_lines = gpu_types::prelude().lines().count();
        assert_eq!(composed.locate(1).0, "prelude (src/render/gpu_types.rs)");
        assert_eq!(composed.locate(prelude_lines + 1), ("common.wgsl", 1));
        let common_lines = COMMON.text.lines().count();
        assert_eq!(composed.locate(prelude_lines + common_lines + 2), ("skinning.wgsl", 2));
    }
}
