//! The shadow pass: each layer (a sun cascade, a spot's map, a cube face) drawn into its tile of
//! the shadow atlas ([`super::shadow_atlas`]), and for a light whose method reads a colour map
//! (moments, blurred once drawn, or depth in colour) that map in the same tile of the colour
//! atlas. A page's tiles are drawn in one render pass, each tile filled first (cleared, or its
//! casters at rest put back: [`super::tile_fill`]) with the viewport on it.
//!
//! A layer's map is kept from frame to frame and drawn (and blurred) again only when the version
//! the world gives it differs from the one it was drawn at (its light was dirty), or its tile is
//! new to it; with an update budget, the out-of-date layers take turns ([`plan_updates`]) and
//! those left waiting are sampled with the projection their map was drawn with.

use super::RenderError;
use super::frame::LayerKey;
use super::frame::{FrameData, LayerDraw};
use super::gpu_types::{Fill, GpuLayer};
use super::instances::{InstanceBuffer, layer_calls};
use super::mesh::{Drawables, JointPalette, Pipelines, Recipe};
use super::moment_blur::{MomentBlur, MomentInput, MomentTile, MomentWork, passes_per_page};
use super::moment_compute::ComputeStores;
use super::moment_samples::SampleScratch;
use super::moments::{ColourFormat, ColourLayout, far_moments};
use super::shaders::{Composed, SHADOW_MODULE};
use super::shadow_atlas::{Placement, ShadowMaps, depth_texture};
use super::shadow_stats::ShadowStats;
pub use super::shadow_tiles::DrawOptions;
use super::shadow_tiles::{Job, page_passes, shadow_variant};
use super::static_maps::StaticMaps;
use super::texture::MaterialTextures;
use super::tile_fill::{FillKind, TileFill};
use super::timing::{PassTimer, Stamps};
use super::uniform_array::UniformArray;
use crate::components::ShadowMethod;
use crate::settings::ShadowDepth;
use crate::shadow::{AtlasShape, MIN_TILE, Tile, TileState, Update, distinct_pages, plan_updates};
use std::collections::{HashMap, HashSet};

mod jobs;
mod sampled;

/// The pipelines that draw into depth maps of one format: depth alone, depth with a colour
/// map of each [`ColourFormat`] (indexed by it), and depth alone multisampled (2, 4 and 8
/// samples a texel, for moments resolved from it).
struct PipelineSet {
    depth: Pipelines,
    colour: [Pipelines; ColourFormat::ALL.len()],
    multisampled: [Pipelines; 3],
}

/// Where the pipelines of `samples` samples a texel are in [`PipelineSet::multisampled`].
fn multisampled(samples: u32) -> usize {
    (samples.trailing_zeros() as usize).clamp(1, 3) - 1
}

impl PipelineSet {
    /// The pipelines for a layer with a colour map of `colour` (or none).
    fn get(&self, colour: Option<ColourFormat>) -> &Pipelines {
        colour.map_or(&self.depth, |f| &self.colour[f as usize])
    }

    fn get_mut(&mut self, colour: Option<ColourFormat>, samples: u32) -> &mut Pipelines {
        match colour {
            _ if samples > 1 => &mut self.multisampled[multisampled(samples)],
            Some(f) => &mut self.colour[f as usize],
            None => &mut self.depth,
        }
    }
}

/// Pipelines, per-layer matrices, the atlas and where its layers are.
pub struct ShadowPass {
    /// The pipelines for each [`ShadowDepth`] (indexed by it).
    sets: [PipelineSet; 2],
    blur: Option<MomentBlur>,
    /// The moment formats the device makes in compute.
    compute: ComputeStores,
    layer_uniforms: UniformArray,
    /// This frame's instanced casters: their object numbers and every object's placement.
    instances: InstanceBuffer,
    fill: TileFill,
    /// The current atlas.
    pub maps: ShadowMaps,
    placement: Placement,
    /// What each layer's tile was last drawn as.
    drawn: HashMap<LayerKey, Drawn>,
    /// The static atlas, made when first needed.
    statics: Option<StaticMaps>,
    /// The multisampled depth moment layers are drawn into, made when first needed.
    scratch: Option<SampleScratch>,
    /// The device can read a depth texture's values, which putting a static map back needs.
    reads_depth: bool,
    /// Frames planned so far: the clock stale layers' ages are counted in.
    frame: u64,
    /// The world's update the last plan was for (see [`crate::components::Time::updates`]).
    planned_for: Option<u64>,
    /// The frame each layer left waiting went out of date.
    stale_since: HashMap<LayerKey, u64>,
    /// This frame's plan, by index in its layers: drawn, or left stale (and for how long).
    plan: Vec<Planned>,
    /// Most draws a submission of the pass holds between tiles (0: no limit; see
    /// [`super::parts`]).
    pub part_draws: usize,
}

/// What the plan does with one layer this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Planned {
    draw: bool,
    /// Frames it has waited, if it is out of date and left waiting.
    waits: Option<u32>,
}

/// What a layer's tile holds: the version of its light's layer it was drawn at, where, for a
/// moment layer the method whose moments it stores, the blur it got and the samples a texel it
/// was resolved from, and the layer's uniform
/// as it was drawn (a stale map is sampled with it). A light's method or the blur can change with
/// no layer dirty (they do not move a shadow); a moment map drawn for another of them must be
/// drawn again all the same.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Drawn {
    version: u64,
    tile: Tile,
    moments: Option<(ShadowMethod, u32, u32)>,
    gpu: GpuLayer,
}

impl ShadowPass {
    /// Builds the shadow pipelines for a device that `reads_depth` (copies depth textures) and
    /// makes moments of the formats `compute` says in compute; `object_layout` is the per-object
    /// bind group layout.
    pub fn new(
        device: &wgpu::Device,
        reads_depth: bool,
        compute: ComputeStores,
        object_layout: &wgpu::BindGroupLayout,
        palette: &JointPalette,
        textures: &MaterialTextures,
    ) -> Self {
        // The moments' compute resolve reads the layers too.
        let computes = if compute.any() { wgpu::ShaderStages::COMPUTE } else { wgpu::ShaderStages::NONE };
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT | computes;
        let layer_uniforms = UniformArray::new(device, "shadow layers", size_of::<GpuLayer>() as u64, stages);
        let module = Composed::new(SHADOW_MODULE).module(device);
        let recipe = |fragment, targets: Vec<_>, depth: ShadowDepth, samples| Recipe {
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
            samples,
        };
        let groups = [&layer_uniforms.layout, object_layout];
        let set = |depth: ShadowDepth| {
            let pipelines = |fragment, targets, samples| {
                Pipelines::new(device, recipe(fragment, targets, depth, samples), groups, palette, textures)
            };
            let colour = ColourFormat::ALL.map(|f| pipelines("fs_moments", vec![Some(f.texture().into())], 1));
            let multisampled = [2, 4, 8].map(|n| pipelines("fs_shadow", Vec::new(), n));
            PipelineSet { depth: pipelines("fs_shadow", Vec::new(), 1), colour, multisampled }
        };
        let sets = [set(ShadowDepth::Float32), set(ShadowDepth::Unorm16)];
        let shape = AtlasShape { page: MIN_TILE, pages: 1 };
        let maps = ShadowMaps::new(device, shape, ColourLayout::NONE, ShadowDepth::default());
        ShadowPass {
            sets,
            blur: None,
            compute,
            layer_uniforms,
            instances: InstanceBuffer::new(device, &palette.layout),
            fill: TileFill::new(device),
            maps,
            placement: Placement::new(shape),
            drawn: HashMap::new(),
            statics: None,
            scratch: None,
            reads_depth,
            frame: 0,
            planned_for: None,
            stale_since: HashMap::new(),
            plan: Vec::new(),
            part_draws: 0,
        }
    }

    /// Makes sure the atlas has `shape`, depth `depth` and colour pages of `colour`; true if it
    /// was made anew (then every layer is drawn again, and whoever samples it must bind it again).
    pub fn ensure_maps(
        &mut self,
        device: &wgpu::Device,
        shape: AtlasShape,
        colour: ColourLayout,
        depth: ShadowDepth,
    ) -> bool {
        let m = &self.maps;
        if m.shape == shape && m.moments.layout() == colour && m.depth == depth {
            return false;
        }
        self.maps = ShadowMaps::new(device, shape, colour, depth);
        if self.placement.shape() != shape {
            self.placement = Placement::new(shape);
        }
        self.drawn.clear();
        self.statics = None;
        if let Some(format) = colour.format.filter(|f| f.moments())
            && self.blur.as_ref().is_none_or(|b| b.format() != format)
        {
            self.blur = Some(MomentBlur::new(
                device,
                format,
                &self.layer_uniforms.layout,
                self.compute.stores(format.texture()),
            ));
        }
        true
    }

    /// Gives every layer of `data` its tile of the atlas (see [`Placement::place`]).
    pub fn place(&mut self, data: &mut FrameData) {
        self.placement.place(data);
    }

    /// Places `data`'s layers and chooses those drawn this frame within the update budget of
    /// `how` ([`plan_updates`]); a layer left waiting is sampled as it was drawn (its uniform in
    /// `data` takes the projection its map has). Call before the main pass uploads `data`.
    ///
    /// The budget is spent once per `update` of the world: another picture of the same update
    /// (a measurement's second pass) draws only empty tiles, so every picture of it agrees.
    pub fn plan(&mut self, data: &mut FrameData, how: DrawOptions, update: Option<u64>) {
        self.place(data);
        let again = update.is_some() && update == self.planned_for;
        self.planned_for = update;
        self.frame += u64::from(!again);
        let present: HashSet<LayerKey> = data.draws.iter().map(|d| d.key).collect();
        self.drawn.retain(|k, _| present.contains(k));
        self.stale_since.retain(|k, _| present.contains(k));
        let updates: Vec<Update> = data
            .draws
            .iter()
            .map(|l| Update {
                state: l.tile.map_or(TileState::Current, |t| self.state(l, t, how)),
                texels: u64::from(l.resolution).pow(2),
                shows: l.shows,
            })
            .collect();
        let budget = (how.reuse && how.updates > 0).then_some(u64::from(how.updates));
        let draw = match budget {
            Some(_) if again => updates.iter().map(|u| u.state == TileState::Empty).collect(),
            _ => plan_updates(&updates, budget, how.max_stale),
        };
        self.plan = updates
            .iter()
            .zip(draw)
            .map(|(u, draw)| match u.state {
                TileState::Stale { age } if !draw => Planned { draw, waits: Some(age) },
                _ => Planned { draw, waits: None },
            })
            .collect();
        for (layer, planned) in data.draws.iter().zip(&self.plan) {
            if planned.waits.is_none() {
                self.stale_since.remove(&layer.key);
                continue;
            }
            self.stale_since.entry(layer.key).or_insert(self.frame);
            if let Some(drawn) = self.drawn.get(&layer.key) {
                let slot = layer.slot as usize;
                data.layers[slot] = as_drawn(data.layers[slot], &drawn.gpu);
            }
        }
    }

    /// What `layer`'s `tile` holds against what the layer is now (every map is empty without
    /// `how.reuse`).
    fn state(&self, layer: &LayerDraw, tile: Tile, how: DrawOptions) -> TileState {
        let Some(drawn) = self.drawn.get(&layer.key).filter(|_| how.reuse && !layer.fresh) else {
            return TileState::Empty;
        };
        if drawn.tile != tile || drawn.moments != self.moments_of(layer, how) {
            TileState::Empty
        } else if drawn.version == layer.version {
            TileState::Current
        } else {
            let since = self.stale_since.get(&layer.key).copied().unwrap_or(self.frame);
            TileState::Stale { age: u32::try_from(self.frame - since).unwrap_or(u32::MAX) }
        }
    }

    /// Makes the static atlas, of the atlas's shape, unless it is there.
    fn ensure_statics(&mut self, device: &wgpu::Device) {
        let m = &self.maps;
        let shape = (m.shape.page, m.pages.layer_views.len() as u32, depth_texture(m.depth));
        if self.statics.as_ref().is_none_or(|s| !s.fits(shape)) {
            self.statics = Some(StaticMaps::new(device, shape.0, shape.1, shape.2));
        }
    }

    /// The format of layer `layer`'s colour map, if its method reads one and there are colour
    /// maps.
    fn colour_format(&self, layer: &LayerDraw) -> Option<ColourFormat> {
        self.maps.moments.format.filter(|_| layer.method.colour_map())
    }

    /// Layer `layer` keeps a moment map (made, and blurred, once it is drawn).
    fn has_moment_map(&self, layer: &LayerDraw) -> bool {
        layer.method.moments() && self.colour_format(layer).is_some()
    }

    /// The colour target layer `layer` is drawn with, if any: its colour map's, unless that holds
    /// moments resolved from the depth map afterwards (with `from_depth`).
    fn colour_target(&self, layer: &LayerDraw, from_depth: bool) -> Option<ColourFormat> {
        self.colour_format(layer).filter(|_| !(from_depth && layer.method.moments()))
    }

    /// Samples a texel of the multisampled depth `layer`'s moments are resolved from as `how`
    /// says (1: its depth map's, not multisampled).
    fn samples(&self, layer: &LayerDraw, how: DrawOptions) -> u32 {
        if self.has_moment_map(layer) && how.moments_from.from_depth() { how.samples.max(1) } else { 1 }
    }

    /// What `layer`'s colour map holds drawn as `how` says: its method, its blur and the
    /// samples its moments were resolved from (no blur for depth in colour).
    fn moments_of(&self, layer: &LayerDraw, how: DrawOptions) -> Option<(ShadowMethod, u32, u32)> {
        let blur = if layer.method.moments() { how.blur } else { 0 };
        self.colour_format(layer).map(|_| (layer.method, blur, self.samples(layer, how)))
    }

    /// Draws the layers [`ShadowPass::plan`] chose, each tile filled and then given the casters
    /// inside its volume (with `instancing`, a depth-only layer's rigid opaque
    /// casters in one call per mesh; with the static cache, only its moving casters over its
    /// casters at rest put back), and blurs the moment layers among them by `blur` texels; the
    /// others keep their maps. Returns what it did. With [`ShadowPass::part_draws`] it submits
    /// what `encoder` holds and waits for it between tiles, as often as that takes.
    pub fn encode(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        encoder: &mut wgpu::CommandEncoder,
        data: &FrameData,
        with: Drawables<'_>,
        how: DrawOptions,
        timer: Option<&mut PassTimer>,
    ) -> Result<ShadowStats, RenderError> {
        let DrawOptions { reuse, blur, static_cache, moments_from, .. } = how;
        let from_depth = moments_from.from_depth();
        if let Some(statics) = &mut self.statics {
            statics.forget_others(&data.draws.iter().map(|d| d.key).collect());
        }
        let mut stats = ShadowStats::default();
        let everything = Planned { draw: true, waits: None };
        let plan = self.plan.iter().copied().chain(std::iter::repeat(everything));
        let todo: Vec<(&LayerDraw, Tile)> = data
            .draws
            .iter()
            .zip(plan)
            .filter_map(|(l, planned)| {
                let tile = l.tile?;
                stats.count((l.light, l.page.is_some()), planned.draw, planned.waits);
                planned.draw.then(|| {
                    stats.count_texels(u64::from(l.resolution).pow(2));
                    (l, tile)
                })
            })
            .collect();
        let uniforms: Vec<GpuLayer> = todo.iter().map(|(l, _)| data.layers[l.slot as usize]).collect();
        self.layer_uniforms.write(device, queue, &uniforms);
        let split = reuse && static_cache && self.reads_depth;
        if split && todo.iter().any(|(l, _)| self.colour_target(l, from_depth).is_none()) {
            self.ensure_statics(device);
        }
        let jobs = self.jobs((device, queue), data, &todo, how, split);
        self.prepare((device, queue), data, &jobs, &mut stats);
        // Layers resolved from multisampled depth are drawn apart, each into the scratch (let
        // go of when MSAA is off).
        let (sampled, jobs): (Vec<Job>, Vec<Job>) = jobs.into_iter().partition(|j| j.samples > 1);
        if how.samples <= 1 {
            self.scratch = None;
        }
        self.ensure_scratch(device, &sampled);
        let input = if from_depth {
            MomentInput::Depth { pages: &self.maps.pages.array_view, layers: &self.layer_uniforms }
        } else {
            MomentInput::Drawn
        };
        let per_page = passes_per_page(&input, blur);
        let made: Vec<MomentTile> = (jobs.iter().filter(|j| per_page > 0 && self.has_moment_map(j.layer)))
            .chain(&sampled)
            .map(|j| self.moment_tile(j))
            .collect();
        let atlas = made.len() - sampled.len();
        let work = MomentWork { maps: &self.maps.moments, tiles: &made[..atlas], first: 0, radius: blur, input };
        let mut passes = self.passes(&jobs);
        if let Some(b) = &self.blur {
            passes += b.passes(&work);
            stats.moments_in_compute = if b.in_compute(&work) { atlas as u32 } else { 0 };
        }
        passes += self.sampled_passes((&made[atlas..], atlas), blur, &mut stats);
        let mut stamps = Stamps { timer, next: 0, total: passes };
        self.encode_jobs((device, queue), encoder, data, &jobs, with, &mut stamps)?;
        if let Some(moment_blur) = self.blur.as_mut().filter(|_| !made.is_empty()) {
            moment_blur.write((device, queue), &made, self.maps.moments.scale, blur);
        }
        if let Some(moment_blur) = self.blur.as_ref().filter(|_| atlas > 0) {
            moment_blur.encode(device, encoder, work, &mut stamps);
        }
        self.encode_sampled(device, encoder, (data, with), (&sampled, &made[atlas..], atlas), blur, &mut stamps);
        for job in jobs.iter().chain(&sampled) {
            let done = Drawn {
                version: job.layer.version,
                tile: job.tile,
                moments: self.moments_of(job.layer, how),
                gpu: uniforms[job.uniform],
            };
            self.drawn.insert(job.layer.key, done);
            if job.statics.is_some()
                && let Some(statics) = self.statics.as_mut()
            {
                statics.mark_drawn(job.layer.key, job.tile, job.layer.static_version);
            }
        }
        for job in jobs.iter().chain(&sampled).filter(|j| blur > 0 && self.has_moment_map(j.layer)) {
            stats.count_blur(job.layer.light);
        }
        Ok(stats)
    }

    /// Where `job`'s moments go in the colour atlas (its tile, as wide as the layer draws,
    /// scaled down to it) and where its depth is.
    fn moment_tile(&self, job: &Job) -> MomentTile {
        let scale = self.maps.moments.scale;
        let Tile { page, x, y, .. } = job.tile;
        let size = (job.layer.resolution / scale).max(1);
        let tile = Tile { page, x: x / scale, y: y / scale, size };
        MomentTile { tile, depth_origin: [x, y], uniform: job.uniform, samples: job.samples }
    }

    /// The passes the jobs take: per page, one over the static atlas if a static map on it is
    /// redrawn, one for its depth-only tiles, one for its tiles with a colour map, each cut
    /// where the frame is submitted in parts (see [`page_passes`]).
    fn passes(&self, jobs: &[Job]) -> usize {
        let statics = distinct_pages(jobs.iter().filter(|j| j.statics.is_some()).map(|j| j.tile)).len();
        statics + page_passes(jobs, self.part_draws).iter().map(|p| p.passes()).sum::<usize>()
    }

    /// How each layer of `todo` (with its tile) is drawn as `how` says: the calls that draw it,
    /// and, with the static cache (`split`), those that draw its static map first when that must
    /// be redrawn.
    fn jobs<'a>(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        data: &'a FrameData,
        todo: &[(&'a LayerDraw, Tile)],
        how: DrawOptions,
        split: bool,
    ) -> Vec<Job<'a>> {
        let DrawOptions { faces, instancing, moments_from, .. } = how;
        let from_depth = moments_from.from_depth();
        let mut instances = Vec::new();
        let mut calls_of = |casters: &[usize], batch: bool| {
            layer_calls(&data.items, casters, |item| shadow_variant(item, faces), batch, &mut instances)
        };
        let jobs = todo
            .iter()
            .enumerate()
            .map(|(uniform, &(layer, tile))| {
                let colour = self.colour_target(layer, from_depth);
                let samples = self.samples(layer, how);
                let batch = instancing && colour.is_none();
                let job = |statics, over_static, calls| Job {
                    layer,
                    tile,
                    uniform,
                    colour,
                    samples,
                    statics,
                    over_static,
                    calls,
                };
                // A multisampled layer is drawn whole into the scratch: no static map.
                if !(split && colour.is_none() && samples == 1) {
                    return job(None, false, calls_of(&layer.casters, batch));
                }
                let (rest, moving): (Vec<usize>, Vec<usize>) =
                    layer.casters.iter().partition(|&&i| data.items[i].at_rest);
                let held = !layer.fresh
                    && self.statics.as_ref().is_some_and(|s| s.holds(layer.key, tile, layer.static_version));
                let statics = (!held).then(|| calls_of(&rest, batch));
                job(statics, true, calls_of(&moving, batch))
            })
            .collect();
        self.instances.write((device, queue), &instances, &data.items);
        jobs
    }

    /// Builds the pipelines the jobs draw with and uploads their fills: a static map's clear
    /// first, then the tile's own fill (its casters at rest put back, or a clear), job by job
    /// (none for a multisampled job: its scratch is cleared by its pass).
    fn prepare(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        data: &FrameData,
        jobs: &[Job],
        stats: &mut ShadowStats,
    ) {
        let depth = depth_texture(self.maps.depth);
        let mut fills = Vec::new();
        for job in jobs {
            let pipelines = self.sets[self.maps.depth as usize].get_mut(job.colour, job.samples);
            for calls in job.statics.iter().chain([&job.calls]) {
                pipelines
                    .prepare(device, calls.singles.iter().map(|s| s.1).chain(calls.batches.iter().map(|b| b.variant)));
                stats.count_calls(job.layer.light, calls.calls());
            }
            stats.count_static(job.layer.light, job.over_static);
            if job.samples > 1 {
                continue;
            }
            let page = job.tile.page;
            if job.statics.is_some() {
                self.fill.prepare(device, depth, FillKind::Clear(None));
                fills.push(Fill { colour: [0.0; 4], page, _pad0: 0, _pad1: 0, _pad2: 0 });
            }
            self.fill.prepare(device, depth, job.fill_kind());
            let far = far_moments(&data.layers[job.layer.slot as usize]);
            let colour = [far.r as f32, far.g as f32, far.b as f32, far.a as f32];
            fills.push(Fill { colour, page, _pad0: 0, _pad1: 0, _pad2: 0 });
        }
        self.fill.write(device, queue, &fills);
    }
}

/// `now`, sampled as `drawn` was drawn: its projection, texel sizes, cascade range and EVSM
/// warp (what the map holds was made with them); its method, bleeding reduction, moment
/// stabiliser and tile stay `now`'s.
fn as_drawn(now: GpuLayer, drawn: &GpuLayer) -> GpuLayer {
    GpuLayer {
        method: now.method,
        moment_bias: now.moment_bias,
        bleed: now.bleed,
        page: now.page,
        tile: now.tile,
        ..*drawn
    }
}
