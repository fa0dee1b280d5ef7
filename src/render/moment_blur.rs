//! Moment maps made and prefiltered once their layers are drawn: [`MomentBlur`] resolves a
//! layer's depth into moments (from the depth atlas, at its size or smaller, or from the layer's
//! depth drawn multisampled) and blurs them, in one compute dispatch where the device can
//! ([`super::moment_compute`]), else by full-screen passes: the resolve, then along rows into a
//! scratch map and along columns back. Moments drawn as colour targets are blurred alone.

use super::gpu_types::{Blur, RESOLVE_MAX_RADIUS};
use super::moment_compute::{ComputeTile, ComputeWork, MomentCompute};
use super::moments::{ColourFormat, ColourMaps};
use super::shaders::{BLUR_MODULE, Composed};
use super::timing::Stamps;
use super::uniform_array::UniformArray;
use crate::shadow::{Tile, distinct_pages};

/// One tile of the colour atlas a [`MomentBlur`] makes: where it is on its colour page (in
/// colour texels), and for a resolve the layer's first texel on the depth page and its uniform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MomentTile {
    /// Its tile of the colour atlas.
    pub tile: Tile,
    /// Its layer's corner on the depth page.
    pub depth_origin: [u32; 2],
    /// Its layer's index in the shadow pass's layer uniforms.
    pub uniform: usize,
    /// Samples per texel of the multisampled depth it is resolved from (1: from the atlas).
    pub samples: u32,
}

/// Where the moments a [`MomentBlur`] blurs come from.
pub enum MomentInput<'a> {
    /// The tiles were drawn as colour targets: blur them.
    Drawn,
    /// Resolve them from the depth atlas (`pages`, its whole array), each with its layer's
    /// uniform in `layers`, and blur them on the way.
    Depth { pages: &'a wgpu::TextureView, layers: &'a UniformArray },
    /// The same from one layer's depth drawn multisampled at the moment map's size (`depth`,
    /// the tile's first texel at its corner; the tile's samples a texel).
    Samples { depth: &'a wgpu::TextureView, layers: &'a UniformArray },
}

impl MomentInput<'_> {
    /// The depth the moments are resolved from, whether it is multisampled, and the layers.
    fn resolved(&self) -> Option<(&wgpu::TextureView, bool, &UniformArray)> {
        match *self {
            MomentInput::Drawn => None,
            MomentInput::Depth { pages, layers } => Some((pages, false, layers)),
            MomentInput::Samples { depth, layers } => Some((depth, true, layers)),
        }
    }
}

/// Moment maps one frame makes: which tiles of which maps, from what, blurred how far.
pub struct MomentWork<'a> {
    /// The colour atlas the tiles are in.
    pub maps: &'a ColourMaps,
    /// The tiles to make.
    pub tiles: &'a [MomentTile],
    /// Where their terms are in what [`MomentBlur::write`] wrote: the first tile's index.
    pub first: usize,
    /// Texels of blur each way (0: none).
    pub radius: u32,
    /// Where their moments come from.
    pub input: MomentInput<'a>,
}

/// The full-screen passes [`MomentBlur::encode`] takes per page: the resolve from depth, if the
/// moments come from it, then rows and columns if they are blurred.
#[must_use]
pub fn passes_per_page(input: &MomentInput<'_>, radius: u32) -> usize {
    usize::from(input.resolved().is_some()) + if radius > 0 { 2 } else { 0 }
}

/// The resolve of depth into moments, and the separable Gaussian blur: one pipeline along rows
/// (layer to scratch), one along columns (scratch back to the layer), for one format.
pub struct MomentBlur {
    format: ColourFormat,
    /// From the depth atlas, and from multisampled depth.
    resolve: [wgpu::RenderPipeline; 2],
    rows: wgpu::RenderPipeline,
    columns: wgpu::RenderPipeline,
    source_layouts: [wgpu::BindGroupLayout; 4],
    uniforms: UniformArray,
    compute: Option<MomentCompute>,
}

fn source_layout(
    device: &wgpu::Device,
    binding: u32,
    dimension: wgpu::TextureViewDimension,
    multisampled: bool,
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("blur source"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: dimension,
                multisampled,
            },
            count: None,
        }],
    })
}

impl MomentBlur {
    /// The blur pipelines for maps of `format`; `layer_layout` is the layout of the shadow
    /// pass's layer uniforms, which a resolve reads (visible to compute where the device
    /// `computes` moments of `format`: then the compute resolve is made too).
    pub fn new(
        device: &wgpu::Device,
        format: ColourFormat,
        layer_layout: &wgpu::BindGroupLayout,
        computes: bool,
    ) -> Self {
        let stages = if computes {
            wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE
        } else {
            wgpu::ShaderStages::FRAGMENT
        };
        let uniforms = UniformArray::new(device, "blur", size_of::<Blur>() as u64, stages);
        let compute =
            computes.then(|| MomentCompute::new(device, format.texture(), &uniforms.layout, layer_layout)).flatten();
        let module = Composed::new(BLUR_MODULE).module(device);
        let source_layouts = [
            source_layout(device, 0, wgpu::TextureViewDimension::D2Array, false),
            source_layout(device, 1, wgpu::TextureViewDimension::D2, false),
            source_layout(device, 2, wgpu::TextureViewDimension::D2Array, false),
            source_layout(device, 3, wgpu::TextureViewDimension::D2, true),
        ];
        let pipeline = |entry: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("blur"),
                bind_group_layouts: groups,
                immediate_size: 0,
            });
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(entry),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_blur"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &[Some(format.texture().into())],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let own = Some(&uniforms.layout);
        let rows = pipeline("fs_blur_rows", &[own, Some(&source_layouts[0])]);
        let columns = pipeline("fs_blur_columns", &[own, Some(&source_layouts[1])]);
        let resolve = [("fs_resolve", 2), ("fs_resolve_samples", 3)]
            .map(|(entry, source)| pipeline(entry, &[own, Some(&source_layouts[source]), Some(layer_layout)]));
        MomentBlur { format, resolve, rows, columns, source_layouts, uniforms, compute }
    }

    /// `work` is made by its one compute dispatch: its moments come from depth into an atlas
    /// compute stores into, blurred no wider than the dispatch reaches.
    #[must_use]
    pub fn in_compute(&self, work: &MomentWork<'_>) -> bool {
        self.compute.is_some()
            && work.input.resolved().is_some()
            && work.maps.storage
            && work.radius <= RESOLVE_MAX_RADIUS
    }

    /// The passes [`MomentBlur::encode`] takes for `work`: one compute pass, or
    /// [`passes_per_page`] full-screen passes on each page it touches.
    #[must_use]
    pub fn passes(&self, work: &MomentWork<'_>) -> usize {
        if work.tiles.is_empty() {
            0
        } else if self.in_compute(work) {
            1
        } else {
            passes_per_page(&work.input, work.radius) * distinct_pages(work.tiles.iter().map(|t| t.tile)).len()
        }
    }

    /// The format its pipelines write.
    pub fn format(&self) -> ColourFormat {
        self.format
    }

    /// Writes the terms of every tile the frame makes (`tiles`, in atlases of `scale` depth
    /// texels a side per moment texel, blurred by `radius`), which each [`MomentBlur::encode`]
    /// of the frame then reads: once a frame, as the writes land before any pass runs.
    pub(super) fn write(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        tiles: &[MomentTile],
        scale: u32,
        radius: u32,
    ) {
        let terms: Vec<Blur> = tiles
            .iter()
            .map(|t| Blur {
                layer: t.tile.page,
                radius: radius as i32,
                size: t.tile.size,
                scale,
                origin: [t.tile.x, t.tile.y],
                depth_origin: t.depth_origin,
                samples: t.samples,
                _pad0: 0,
                _pad1: 0,
                _pad2: 0,
            })
            .collect();
        self.uniforms.write(device, queue, &terms);
    }

    /// Makes `work`'s tiles from its input and blurs them by its radius each way, in one compute
    /// pass where it can ([`MomentBlur::in_compute`]), else with [`passes_per_page`] passes a page
    /// (the resolve into the page, rows into the scratch page, columns back), each stamped as the
    /// frame's next shadow pass. Each tile reads only its own texels.
    pub(super) fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        work: MomentWork<'_>,
        stamps: &mut Stamps<'_>,
    ) {
        let in_compute = self.in_compute(&work);
        let MomentWork { maps, tiles, first, radius, input } = work;
        if let (Some(compute), Some((depth, multisampled, layers))) = (&self.compute, input.resolved())
            && in_compute
        {
            let tiles: Vec<ComputeTile> = tiles
                .iter()
                .enumerate()
                .map(|(i, t)| ComputeTile { blur: first + i, layer: t.uniform, size: t.tile.size })
                .collect();
            let (moments, blur) = (&maps.array_view, &self.uniforms);
            compute.encode(
                device,
                encoder,
                ComputeWork { depth, multisampled, moments, blur, layers, tiles: &tiles },
                stamps,
            );
            return;
        }
        let group = |layout: &wgpu::BindGroupLayout, binding: u32, view: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("blur source"),
                layout,
                entries: &[wgpu::BindGroupEntry { binding, resource: wgpu::BindingResource::TextureView(view) }],
            })
        };
        let resolve = input.resolved().map(|(depth, multisampled, layers)| {
            let (source, binding) = if multisampled { (3, 3) } else { (2, 2) };
            (&self.resolve[usize::from(multisampled)], group(&self.source_layouts[source], binding, depth), layers)
        });
        let from_array = group(&self.source_layouts[0], 0, &maps.array_view);
        let from_scratch = group(&self.source_layouts[1], 1, &maps.scratch_view);
        for page in distinct_pages(tiles.iter().map(|t| t.tile)) {
            let Some(target) = maps.layer_views.get(page as usize) else { continue };
            let mut passes = Vec::new();
            if let Some((pipeline, from_depth, layers)) = &resolve {
                passes.push((*pipeline, from_depth, target, Some(*layers)));
            }
            if radius > 0 {
                passes.push((&self.rows, &from_array, &maps.scratch_view, None));
                passes.push((&self.columns, &from_scratch, target, None));
            }
            for (pipeline, source, view, layers) in passes {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("moment blur"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        // The page's other tiles keep what they hold.
                        ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: stamps.next(),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(1, source, &[]);
                for (i, t) in tiles.iter().enumerate().filter(|(_, t)| t.tile.page == page) {
                    let Tile { x, y, size, .. } = t.tile;
                    pass.set_viewport(x as f32, y as f32, size as f32, size as f32, 0.0, 1.0);
                    pass.set_scissor_rect(x, y, size, size);
                    pass.set_bind_group(0, &self.uniforms.bind_group, &[self.uniforms.offset(first + i)]);
                    if let Some(layers) = layers {
                        pass.set_bind_group(2, &layers.bind_group, &[layers.offset(t.uniform)]);
                    }
                    pass.draw(0..3, 0..1);
                }
            }
        }
    }
}
