//! The shadow pass: depth, one layer of a 2D array texture per spot light, sun cascade or cube
//! face, and for a light whose method reads a colour map (moments, blurred once drawn, or depth
//! in colour) that map in the same slot of a colour array.
//!
//! A layer's map is kept from frame to frame and drawn (and blurred) again only when the version
//! the world gives it differs from the one it was drawn at (its light was dirty).

use super::extract::{DrawItem, FrameData, LayerDraw};
use super::gpu_types::GpuLayer;
use super::instances::{InstanceBuffer, LayerCalls, layer_calls};
use super::mesh::{AlphaClass, Drawables, JointPalette, Pipelines, Recipe, Variant};
use super::moments::{ColourFormat, ColourMaps, MomentBlur, far_moments};
use super::shaders::{Composed, SHADOW_MODULE};
use super::static_maps::StaticMaps;
use super::texture::{LayeredTarget, MaterialTextures};
use super::timing::PassTimer;
use super::uniform_array::UniformArray;
use crate::components::{AlphaMode, ShadowMethod};
use crate::settings::{ShadowDepth, ShadowFaces};
use crate::light::LightLabel;
use bevy_ecs::prelude::*;

/// The shadow-map array and the views the two passes use.
pub struct ShadowMaps {
    /// Width and height of each layer.
    pub size: u32,
    /// Number of layers (see [`array_layers`]).
    pub layers: u32,
    /// Their depth format.
    pub depth: ShadowDepth,
    /// The depth texture (a copy destination where depth can be copied).
    texture: wgpu::Texture,
    /// One render view per layer.
    layer_views: Vec<wgpu::TextureView>,
    /// The whole array, for sampling.
    pub array_view: wgpu::TextureView,
    /// The colour maps, slot for slot (a stand-in when no light uses one).
    pub moments: ColourMaps,
}

/// The texture format of depth maps of `depth`.
pub(super) fn depth_texture(depth: ShadowDepth) -> wgpu::TextureFormat {
    match depth {
        ShadowDepth::Float32 => wgpu::TextureFormat::Depth32Float,
        ShadowDepth::Unorm16 => wgpu::TextureFormat::Depth16Unorm,
    }
}

/// The pipelines that draw into depth maps of one format: depth alone, and depth with a colour
/// map of each [`ColourFormat`] (indexed by it).
struct PipelineSet {
    depth: Pipelines,
    colour: [Pipelines; 4],
}

impl PipelineSet {
    /// The pipelines for a layer with a colour map of `colour` (or none).
    fn get(&self, colour: Option<ColourFormat>) -> &Pipelines {
        colour.map_or(&self.depth, |f| &self.colour[f as usize])
    }

    fn get_mut(&mut self, colour: Option<ColourFormat>) -> &mut Pipelines {
        match colour {
            Some(f) => &mut self.colour[f as usize],
            None => &mut self.depth,
        }
    }
}

/// Pipelines, per-layer matrices and the shadow-map array.
pub struct ShadowPass {
    /// The pipelines for each [`ShadowDepth`] (indexed by it).
    sets: [PipelineSet; 2],
    blur: Option<MomentBlur>,
    layer_uniforms: UniformArray,
    /// The placements of this frame's instanced casters.
    instances: InstanceBuffer,
    /// The current shadow maps.
    pub maps: ShadowMaps,
    /// What each layer of `maps` was last drawn as.
    drawn: Vec<Option<Drawn>>,
    /// The device can copy depth textures, so the static maps can be used.
    copies_depth: bool,
    /// The static part of the depth maps, made when first needed.
    statics: Option<StaticMaps>,
}

/// What a layer's maps hold: the version of its light's layer they were drawn at and, for a
/// moment layer, the method whose moments it stores and the blur it got. A light's method or the
/// blur can change with no layer dirty (they do not move a shadow); a moment map drawn for
/// another of them must be drawn again all the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Drawn {
    version: u64,
    moments: Option<(ShadowMethod, u32)>,
}

/// Shadow passes of one frame: per light, how many layers were drawn and how many kept.
#[derive(Resource, Clone, Debug, Default, PartialEq, Eq)]
pub struct ShadowStats {
    /// One entry per light, in layer order.
    pub lights: Vec<LightPasses>,
}

/// One light's shadow passes in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightPasses {
    /// Which light.
    pub light: LightLabel,
    /// Layers drawn this frame.
    pub drawn: u32,
    /// Layers whose map was kept from an earlier frame.
    pub kept: u32,
    /// Moment layers blurred this frame.
    pub blurred: u32,
    /// Draw calls this frame's layers took (an instanced batch is one).
    pub calls: u32,
    /// Layers drawn over a copy of their static map (only their moving casters drawn).
    pub from_static: u32,
}

impl ShadowStats {
    /// Layers drawn this frame, all lights together.
    pub fn drawn(&self) -> u32 {
        self.lights.iter().map(|l| l.drawn).sum()
    }

    /// Layers kept this frame, all lights together.
    pub fn kept(&self) -> u32 {
        self.lights.iter().map(|l| l.kept).sum()
    }

    /// Draw calls of this frame's layers, all lights together.
    pub fn calls(&self) -> u32 {
        self.lights.iter().map(|l| l.calls).sum()
    }

    /// Moment layers blurred this frame, all lights together.
    pub fn blurred(&self) -> u32 {
        self.lights.iter().map(|l| l.blurred).sum()
    }

    fn count(&mut self, light: LightLabel, drawn: bool) {
        if self.lights.last().is_none_or(|l| l.light != light) {
            self.lights.push(LightPasses { light, drawn: 0, kept: 0, blurred: 0, calls: 0, from_static: 0 });
        }
        let entry = self.lights.last_mut().expect("pushed above");
        if drawn { entry.drawn += 1 } else { entry.kept += 1 }
    }

    /// Layers drawn over a copy of their static map, all lights together.
    pub fn from_static(&self) -> u32 {
        self.lights.iter().map(|l| l.from_static).sum()
    }

    fn count_static(&mut self, light: LightLabel, over_static: bool) {
        if let Some(entry) = self.lights.iter_mut().find(|l| l.light == light) {
            entry.from_static += over_static as u32;
        }
    }

    fn count_calls(&mut self, light: LightLabel, calls: usize) {
        if let Some(entry) = self.lights.iter_mut().find(|l| l.light == light) {
            entry.calls += calls as u32;
        }
    }

    fn count_blur(&mut self, light: LightLabel) {
        if let Some(entry) = self.lights.iter_mut().find(|l| l.light == light) {
            entry.blurred += 1;
        }
    }
}

impl std::fmt::Display for ShadowStats {
    /// "sun 1/3 · spot 1 0/1": layers drawn / kept, per light.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, l) in self.lights.iter().enumerate() {
            write!(f, "{}{} {}/{}", if i > 0 { " · " } else { "" }, l.light, l.drawn, l.kept)?;
        }
        Ok(())
    }
}

impl ShadowPass {
    /// Builds the shadow pipelines; `object_layout` is the per-object bind group layout.
    pub fn new(
        (device, copies_depth): (&wgpu::Device, bool),
        object_layout: &wgpu::BindGroupLayout,
        palette: &JointPalette,
        textures: &MaterialTextures,
        size: u32,
    ) -> Self {
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let layer_uniforms = UniformArray::new(device, "shadow layers", size_of::<GpuLayer>() as u64, stages);
        let module = Composed::new(SHADOW_MODULE).module(device);
        let recipe = |fragment, targets: Vec<_>, depth: ShadowDepth| Recipe {
            label: "shadow",
            module: module.clone(),
            vertex: "vs_shadow",
            fragment,
            targets,
            depth: wgpu::DepthStencilState {
                format: depth_texture(depth),
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: Default::default(),
                // Biasing is done when sampling, in texel units, so it works the same on every backend.
                bias: Default::default(),
            },
            samples_shadows: false,
        };
        let groups = [&layer_uniforms.layout, object_layout];
        let set = |depth: ShadowDepth| {
            let pipelines =
                |fragment, targets| Pipelines::new(device, recipe(fragment, targets, depth), groups, palette, textures);
            let colour = [ColourFormat::Half, ColourFormat::Full, ColourFormat::R16, ColourFormat::R32]
                .map(|f| pipelines("fs_moments", vec![Some(f.texture().into())]));
            PipelineSet { depth: pipelines("fs_shadow", Vec::new()), colour }
        };
        let sets = [set(ShadowDepth::Float32), set(ShadowDepth::Unorm16)];
        let maps = ShadowMaps::new(device, (size, 2, copies_depth), None, ShadowDepth::default());
        let instances = InstanceBuffer::new(device);
        let drawn = vec![None; 2];
        ShadowPass { sets, blur: None, layer_uniforms, instances, maps, drawn, copies_depth, statics: None }
    }

    /// Makes sure the maps are `size` texels of `depth`, hold `layers` and have colour maps of
    /// `colour`; true if they were re-created (then every layer must be drawn again).
    pub fn ensure_maps(
        &mut self,
        device: &wgpu::Device,
        (size, layers): (u32, usize),
        colour: Option<ColourFormat>,
        depth: ShadowDepth,
    ) -> bool {
        let layers = array_layers(layers);
        let m = &self.maps;
        if m.size == size && m.layers >= layers && m.moments.format == colour && m.depth == depth {
            return false;
        }
        self.maps = ShadowMaps::new(device, (size, layers, self.copies_depth), colour, depth);
        self.drawn = vec![None; layers as usize];
        self.statics = None;
        if let Some(format) = colour.filter(|f| f.moments())
            && self.blur.as_ref().is_none_or(|b| b.format() != format)
        {
            self.blur = Some(MomentBlur::new(device, format));
        }
        true
    }

    /// Makes the static maps, of the shadow maps' shape, unless they are there.
    fn ensure_statics(&mut self, device: &wgpu::Device) {
        let m = &self.maps;
        let shape = (m.size, m.layers, depth_texture(m.depth));
        if self.statics.as_ref().is_none_or(|s| !s.fits(shape)) {
            self.statics = Some(StaticMaps::new(device, shape.0, shape.1, shape.2));
        }
    }

    /// The colour format layer `layer` is drawn in, if its method reads a colour map and there
    /// are colour maps.
    fn colour_format(&self, layer: &LayerDraw) -> Option<ColourFormat> {
        self.maps.moments.format.filter(|_| layer.method.colour_map())
    }

    /// What `layer` is drawn as with moment maps blurred by `blur` texels.
    fn drawn_as(&self, layer: &LayerDraw, blur: u32) -> Drawn {
        let blur = if layer.method.moments() { blur } else { 0 };
        Drawn { version: layer.version, moments: self.colour_format(layer).map(|_| (layer.method, blur)) }
    }

    /// True when `layer` must be drawn: its slot holds something else, or nothing is reused.
    fn needs_drawing(&self, layer: &LayerDraw, reuse: bool, blur: u32) -> bool {
        !reuse || self.drawn.get(layer.slot as usize).copied().flatten() != Some(self.drawn_as(layer, blur))
    }

    /// Draws the layers that need it (all of them unless `reuse`), each cleared to far and then
    /// given the casters inside its volume (with `instancing`, a depth-only layer's rigid opaque
    /// casters in one call per mesh; with the static cache, only its moving casters over a copy
    /// of its static map), and blurs the moment layers among them by `blur` texels; the others
    /// keep their maps. Returns what it did.
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        with: Drawables<'_>,
        how: DrawOptions,
        mut timer: Option<&mut PassTimer>,
    ) -> ShadowStats {
        let DrawOptions { reuse, faces, blur, instancing, static_cache } = how;
        let mut stats = ShadowStats::default();
        let todo: Vec<&LayerDraw> = data
            .draws
            .iter()
            .filter(|l| {
                let draw = self.needs_drawing(l, reuse, blur);
                stats.count(l.light, draw);
                draw
            })
            .filter(|l| (l.slot as usize) < self.maps.layer_views.len())
            .collect();
        let uniforms: Vec<GpuLayer> = todo.iter().map(|l| data.layers[l.slot as usize]).collect();
        self.layer_uniforms.write(device, queue, &uniforms);
        let split = reuse && static_cache && self.copies_depth;
        if split && todo.iter().any(|l| self.colour_format(l).is_none()) {
            self.ensure_statics(device);
        }
        let mut placements = Vec::new();
        let mut calls_of = |casters: &[usize], batch: bool| {
            layer_calls(&data.items, casters, |item| shadow_variant(item, faces), batch, &mut placements)
        };
        let jobs: Vec<Job> = todo
            .iter()
            .enumerate()
            .map(|(uniform, &layer)| {
                let depth_only = self.colour_format(layer).is_none();
                let batch = instancing && depth_only;
                if !(split && depth_only) {
                    return Job {
                        layer,
                        uniform,
                        statics: None,
                        over_static: false,
                        calls: calls_of(&layer.casters, batch),
                    };
                }
                let (rest, moving): (Vec<usize>, Vec<usize>) =
                    layer.casters.iter().partition(|&&i| data.items[i].at_rest);
                let held = self.statics.as_ref().is_some_and(|s| s.holds(layer.slot, layer.static_version));
                let statics = (!held).then(|| calls_of(&rest, batch));
                Job { layer, uniform, statics, over_static: true, calls: calls_of(&moving, batch) }
            })
            .collect();
        self.instances.write(device, queue, &placements);
        for job in &jobs {
            let format = self.colour_format(job.layer);
            let pipelines = self.sets[self.maps.depth as usize].get_mut(format);
            for calls in job.statics.iter().chain([&job.calls]) {
                pipelines
                    .prepare(device, calls.singles.iter().map(|s| s.1).chain(calls.batches.iter().map(|b| b.variant)));
                stats.count_calls(job.layer.light, calls.calls());
            }
            stats.count_static(job.layer.light, job.over_static);
        }
        let blurred: Vec<&LayerDraw> = todo
            .iter()
            .copied()
            .filter(|l| blur > 0 && l.method.moments() && self.colour_format(l).is_some())
            .collect();
        let passes = jobs.len() + jobs.iter().filter(|j| j.statics.is_some()).count() + 2 * blurred.len();
        let mut next_pass = 0..;
        let drawing =
            Drawing { with, items: &data.items, layers: &self.layer_uniforms, instances: self.instances.buffer() };
        for job in &jobs {
            let (layer, slot) = (job.layer, job.layer.slot as usize);
            let format = self.colour_format(layer);
            let pipelines = self.sets[self.maps.depth as usize].get(format);
            if let Some(calls) = &job.statics {
                let statics = self.statics.as_mut().expect("made above");
                statics.mark_drawn(layer.slot, layer.static_version);
                let writes = next_pass.next().and_then(|i| timer.as_deref_mut()?.shadow_writes(i, passes));
                let depth = (statics.view(layer.slot), wgpu::LoadOp::Clear(1.0));
                drawing.pass(encoder, depth, None, writes, (job.uniform, pipelines), calls);
            }
            let load = if job.over_static {
                self.statics.as_ref().expect("made above").copy_into(encoder, layer.slot, &self.maps.texture);
                wgpu::LoadOp::Load
            } else {
                wgpu::LoadOp::Clear(1.0)
            };
            let colour = format.map(|_| wgpu::RenderPassColorAttachment {
                view: &self.maps.moments.layer_views[slot],
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(far_moments(&data.layers[slot])),
                    store: wgpu::StoreOp::Store,
                },
            });
            let writes = next_pass.next().and_then(|i| timer.as_deref_mut()?.shadow_writes(i, passes));
            drawing.pass(
                encoder,
                (&self.maps.layer_views[slot], load),
                colour,
                writes,
                (job.uniform, pipelines),
                &job.calls,
            );
            let done = self.drawn_as(layer, blur);
            if let Some(drawn) = self.drawn.get_mut(slot) {
                *drawn = Some(done);
            }
        }
        if let Some(moment_blur) = self.blur.as_mut().filter(|_| !blurred.is_empty()) {
            let slots: Vec<u32> = blurred.iter().map(|l| l.slot).collect();
            let stamps = (timer, next_pass.start, passes);
            moment_blur.encode((device, queue), encoder, (&self.maps.moments, &slots, blur), stamps);
            for layer in blurred {
                stats.count_blur(layer.light);
            }
        }
        stats
    }
}

/// How the shadow pass draws, from the settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawOptions {
    /// Keep clean layers' maps (the cache); without it every layer is drawn, whole.
    pub reuse: bool,
    /// Which faces casters draw.
    pub faces: ShadowFaces,
    /// Blur of moment maps, in texels.
    pub blur: u32,
    /// Draw rigid opaque casters of depth-only layers instanced.
    pub instancing: bool,
    /// Keep casters at rest in static maps (with the cache, where depth can be copied).
    pub static_cache: bool,
}

impl From<&crate::Settings> for DrawOptions {
    fn from(s: &crate::Settings) -> Self {
        DrawOptions {
            reuse: s.reuse_shadow_maps,
            faces: s.shadow_faces,
            blur: s.moment_blur,
            instancing: s.instancing,
            static_cache: s.static_cache,
        }
    }
}

/// How one layer is drawn this frame.
struct Job<'a> {
    layer: &'a LayerDraw,
    /// Its index in the frame's layer uniforms.
    uniform: usize,
    /// The calls that draw its static map first, when that must be drawn again.
    statics: Option<LayerCalls>,
    /// Drawn over a copy of its static map (`calls` are then its moving casters only).
    over_static: bool,
    /// The calls that draw it.
    calls: LayerCalls,
}

/// What every layer pass of a frame draws with.
struct Drawing<'a> {
    with: Drawables<'a>,
    items: &'a [DrawItem],
    layers: &'a UniformArray,
    instances: &'a wgpu::Buffer,
}

impl Drawing<'_> {
    /// One render pass into `depth` (loaded or cleared as it says) and `colour`, drawing
    /// `calls` with `pipelines` and layer uniform `uniform`.
    fn pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (depth, load): (&wgpu::TextureView, wgpu::LoadOp<f32>),
        colour: Option<wgpu::RenderPassColorAttachment<'_>>,
        timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
        (uniform, pipelines): (usize, &Pipelines),
        calls: &LayerCalls,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("shadow pass"),
            color_attachments: if colour.is_some() { std::slice::from_ref(&colour) } else { &[] },
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.layers.bind_group, &[self.layers.offset(uniform)]);
        pipelines.draw(&mut pass, self.with, self.items, calls.singles.iter().copied());
        pipelines.draw_batches(&mut pass, self.with, &calls.batches, self.instances);
    }
}

/// How a caster is drawn into a shadow map. Both faces by default: a one-sided surface (the
/// ground, a leaf) blocks light from either side, as it does in the ray-traced truth, and on
/// closed meshes the faces towards the light are nearer and win the depth test anyway. With
/// [`ShadowFaces::Back`] the faces turned towards the light (front faces: the light looks along
/// its -Z like a camera) are culled, but never those of a double-sided material. A blended
/// caster is cut out like a masked one.
fn shadow_variant(item: &DrawItem, faces: ShadowFaces) -> Variant {
    let cull = (faces == ShadowFaces::Back && !item.double_sided).then_some(wgpu::Face::Front);
    let alpha = if item.alpha == AlphaMode::Opaque { AlphaClass::Opaque } else { AlphaClass::Mask };
    // Opaque casters have no fragment stage, so whether they have a texture does not matter.
    let textured = alpha == AlphaClass::Mask && item.texture.is_some();
    Variant { skinned: item.skinned, cull, alpha, textured, methods: 0, instanced: false }
}

/// Layers to allocate for `needed`: at least 2 (GL cannot view a single-layer texture as an
/// array) and never a multiple of 6, which the GL backend takes for a cube map or cube array.
fn array_layers(needed: usize) -> u32 {
    let layers = (needed as u32).max(2);
    if layers.is_multiple_of(6) { layers + 1 } else { layers }
}

impl ShadowMaps {
    fn new(
        device: &wgpu::Device,
        (size, layers, copies): (u32, u32, bool),
        colour: Option<ColourFormat>,
        depth: ShadowDepth,
    ) -> Self {
        let extra = if copies { wgpu::TextureUsages::COPY_DST } else { wgpu::TextureUsages::empty() };
        let LayeredTarget { texture, layer_views, array_view } =
            LayeredTarget::copyable(device, "shadow maps", depth_texture(depth), (size, layers), extra);
        let moments = ColourMaps::new(device, colour, size, layers);
        ShadowMaps { size, layers, depth, texture, layer_views, array_view, moments }
    }
}

#[cfg(test)]
mod tests {
    use super::array_layers;

    #[test]
    fn layer_counts_avoid_what_gl_takes_for_cube_maps() {
        assert_eq!(array_layers(0), 2);
        assert_eq!(array_layers(1), 2);
        assert_eq!(array_layers(5), 5);
        assert_eq!(array_layers(6), 7);
        assert_eq!(array_layers(12), 13);
    }
}
