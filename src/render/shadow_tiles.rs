//! The pieces a frame's shadow passes are made of: a page's pass, its timestamps, a tile's job
//! and how it is drawn, and which variant draws a caster.

use super::frame::{DrawItem, LayerDraw};
use super::instances::LayerCalls;
use super::mesh::{AlphaClass, Drawables, Pipelines, Variant};
use super::moments::ColourFormat;
use super::tile_fill::{FillKind, TileFill};
use super::uniform_array::UniformArray;
use crate::components::AlphaMode;
use crate::settings::{MomentSource, ShadowFaces};
use crate::shadow::Tile;

/// The tiles of one page (depth-only, or with a colour map) that one pass draws, or more than
/// one where the frame is submitted in parts between them.
pub(super) struct PagePass {
    pub(super) page: u32,
    pub(super) coloured: bool,
    /// Its jobs (their indices) in the order it records them, each with whether the frame so
    /// far is submitted before it: before the first, ahead of the pass; before a later one, the
    /// pass ended and begun again.
    pub(super) jobs: Vec<(usize, bool)>,
}

impl PagePass {
    /// The render passes it takes: one, and one more for each submission after its first job.
    pub(super) fn passes(&self) -> usize {
        1 + self.jobs.iter().skip(1).filter(|(_, submit)| *submit).count()
    }
}

/// The passes the jobs' tiles take, a page and colour at a time in order, submitted in parts of
/// at most `most` draws where a part can end between tiles (see
/// [`super::parts::submits_before`]; 0: no limit).
pub(super) fn page_passes(jobs: &[Job], most: usize) -> Vec<PagePass> {
    let group = |i: usize| (jobs[i].tile.page, jobs[i].colour.is_some());
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&i| group(i));
    let draws: Vec<usize> = order.iter().map(|&i| jobs[i].calls.calls()).collect();
    let submits = super::parts::submits_before(&draws, most);
    let mut passes: Vec<PagePass> = Vec::new();
    for (i, submit) in order.into_iter().zip(submits) {
        match passes.last_mut() {
            Some(pass) if (pass.page, pass.coloured) == group(i) => pass.jobs.push((i, submit)),
            _ => passes.push(PagePass { page: group(i).0, coloured: group(i).1, jobs: vec![(i, submit)] }),
        }
    }
    passes
}

/// A pass over a page of depth `target` (and of colour, if given), keeping what its other tiles
/// hold, or with its depth cleared to the far plane when `clear`.
pub(super) fn begin<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    (target, colour): (&wgpu::TextureView, Option<&wgpu::TextureView>),
    clear: bool,
    timestamp_writes: Option<wgpu::RenderPassTimestampWrites<'_>>,
) -> wgpu::RenderPass<'e> {
    let keep = |view| wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
    };
    let colour = colour.map(keep);
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("shadow pass"),
        color_attachments: if colour.is_some() { std::slice::from_ref(&colour) } else { &[] },
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: target,
            depth_ops: Some(wgpu::Operations {
                load: if clear { wgpu::LoadOp::Clear(1.0) } else { wgpu::LoadOp::Load },
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes,
        occlusion_query_set: None,
        multiview_mask: None,
    })
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
    /// Texels of out-of-date layers drawn per frame at most (0: no limit).
    pub updates: u32,
    /// Frames a layer may wait before it goes ahead of those that show more.
    pub max_stale: u32,
    /// How moment maps are made.
    pub moments_from: MomentSource,
    /// Samples a texel of the multisampled depth moments from depth are resolved from (1: the
    /// depth map's own texels); the renderer lowers it to what the device allows.
    pub samples: u32,
}

impl From<&crate::settings::MapSettings> for DrawOptions {
    fn from(s: &crate::settings::MapSettings) -> Self {
        DrawOptions {
            reuse: s.reuse_shadow_maps,
            faces: s.shadow_faces,
            blur: s.moment_blur,
            instancing: s.instancing,
            static_cache: s.static_cache,
            updates: s.shadow_updates,
            max_stale: s.max_stale,
            moments_from: s.moments_from,
            samples: s.moment_samples,
        }
    }
}

/// How one layer is drawn this frame.
pub(super) struct Job<'a> {
    pub(super) layer: &'a LayerDraw,
    /// Its tile.
    pub(super) tile: Tile,
    /// Its index in the frame's layer uniforms.
    pub(super) uniform: usize,
    /// Its colour map's format, if it has one.
    pub(super) colour: Option<ColourFormat>,
    /// Samples a texel of the multisampled depth its moments are resolved from (1: drawn into
    /// its tile of the atlas).
    pub(super) samples: u32,
    /// The calls that draw its static map first, when that must be drawn again.
    pub(super) statics: Option<LayerCalls>,
    /// Drawn over its casters at rest put back (`calls` are then its moving casters only).
    pub(super) over_static: bool,
    /// The calls that draw it.
    pub(super) calls: LayerCalls,
}

impl Job<'_> {
    /// Its tile's corner on the page and side.
    pub(super) fn place(&self) -> (u32, u32, u32) {
        (self.tile.x, self.tile.y, self.layer.resolution)
    }

    /// How its tile is filled before its casters are drawn.
    pub(super) fn fill_kind(&self) -> FillKind {
        if self.over_static { FillKind::Restore } else { FillKind::Clear(self.colour.map(ColourFormat::texture)) }
    }
}

/// What every tile of a frame draws with.
pub(super) struct Drawing<'a> {
    pub(super) with: Drawables<'a>,
    pub(super) items: &'a [DrawItem],
    pub(super) layers: &'a UniformArray,
    pub(super) instances: (&'a wgpu::Buffer, &'a wgpu::BindGroup),
}

/// A fill: the pipelines, which one (depth format and kind), its uniform's index and the static
/// atlas's bind group (for a restore); none when the tile is already clear.
pub(super) type FillWith<'a> =
    Option<(&'a TileFill, (wgpu::TextureFormat, FillKind), usize, Option<&'a wgpu::BindGroup>)>;

impl Drawing<'_> {
    /// Draws `job` at `(x, y, side)` of `pass` (its tile, [`Job::place`], or a scratch's
    /// corner): the viewport and scissor there, the tile filled (unless it is clear already),
    /// then `calls` with `pipelines` and the layer's uniform.
    pub(super) fn tile(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        job: &Job,
        (x, y, side): (u32, u32, u32),
        fill: FillWith<'_>,
        (pipelines, calls): (&Pipelines, &LayerCalls),
    ) {
        pass.set_viewport(x as f32, y as f32, side as f32, side as f32, 0.0, 1.0);
        pass.set_scissor_rect(x, y, side, side);
        if let Some((fills, which, index, statics)) = fill {
            fills.draw(pass, which, index, statics);
        }
        pass.set_bind_group(0, &self.layers.bind_group, &[self.layers.offset(job.uniform)]);
        pipelines.draw(pass, self.with, self.items, calls.singles.iter().copied());
        pipelines.draw_batches(pass, self.with, &calls.batches, self.instances);
    }
}

/// How a caster is drawn into a shadow map. Both faces by default: a one-sided surface (the
/// ground, a leaf) blocks light from either side, as it does in the ray-traced truth, and on
/// closed meshes the faces towards the light are nearer and win the depth test anyway. With
/// [`ShadowFaces::Back`] the faces turned towards the light (front faces: the light looks along
/// its -Z like a camera) are culled, but never those of a double-sided material. A blended
/// caster is cut out like a masked one.
pub(super) fn shadow_variant(item: &DrawItem, faces: ShadowFaces) -> Variant {
    let cull = (faces == ShadowFaces::Back && !item.double_sided).then_some(wgpu::Face::Front);
    let alpha = if item.alpha == AlphaMode::Opaque { AlphaClass::Opaque } else { AlphaClass::Mask };
    // Opaque casters have no fragment stage, so whether they have a texture does not matter.
    let textured = alpha == AlphaClass::Mask && item.texture.is_some();
    Variant { skinned: item.skinned, cull, alpha, textured, methods: 0, instanced: false }
}
