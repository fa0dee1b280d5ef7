//! The renderer: uploads meshes, then each frame extracts, runs the shadow pass and the main pass.

use super::bare_depth::BareDepth;
use super::camera_depth::CameraDepth;
use super::depth_reduction::DepthReduction;
use super::extract::{KeptIndex, read_world};
use super::frame::{FrameData, Shadowless};
use super::gpu_types::{GpuLayer, Object};
use super::lines::{LinePass, volume_lines};
use super::main_pass::MainPass;
use super::map_view::{self, MapView};
use super::mesh::{Drawables, GpuMesh, JointPalette};
use super::moment_compute::ComputeStores;
use super::moments;
use super::news::RenderNews;
use super::page_marks::PageMarking;
use super::parts::{PART_DRAWS, Part, SHADOW_PARTS_LARGER};
use super::shadow_pass::{DrawOptions, ShadowPass};
use super::shadow_stats::ShadowStats;
use super::texture::MaterialTextures;
use super::timing::{PassTimer, PassTimes};
use super::uniform_array::UniformArray;
use super::{Gpu, RenderError};
use crate::assets::{MeshLibrary, TextureLibrary};
use crate::light::LightLabel;
use crate::settings::FrameSettings;
use crate::shadow::FitMode;
use crate::systems::{ShadowAtlas, ShadowCaps};
use bevy_ecs::prelude::*;

mod samples;

/// Where a frame goes: a picture, or the measuring targets.
enum Output<'a> {
    Picture(&'a wgpu::TextureView),
    /// The measuring targets, reporting lights from the given one on.
    Measure(&'a [wgpu::TextureView; 3], usize),
    /// A grid target of the given size, the probe points to draw into it, and the first light
    /// reported.
    Probes(&'a wgpu::TextureView, (u32, u32), &'a wgpu::Buffer, u32, usize),
    /// Nothing but the shadow maps.
    ShadowsOnly,
    /// The shadow maps, then the camera's depth alone, and from it the virtual pages marked and
    /// the SDSM reduction made: what a headless frame draws until its view's pages are in.
    Priming,
}

/// The camera's depth buffer.
struct DepthBuffer {
    /// Its view, as the main pass draws into it.
    view: wgpu::TextureView,
    /// Its depth aspect, which the SDSM reduction reads.
    depth_only: wgpu::TextureView,
    size: (u32, u32),
}

/// The shadow-map viewer's picture: its view, a number that changes whenever the texture behind
/// it is made anew, and whose each tile is.
pub struct MapAtlas<'a> {
    /// The atlas's texture (`Rgba8UnormSrgb`).
    pub texture: &'a wgpu::Texture,
    /// The atlas.
    pub view: &'a wgpu::TextureView,
    /// Changes when the atlas texture is replaced (a texture shown elsewhere must be rebound).
    pub generation: u64,
    /// Each layer's tile.
    pub tiles: Vec<AtlasTile>,
    /// Pages the picture shows.
    pub pages: u32,
}

/// One layer's tile in the shadow-map viewer's picture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtlasTile {
    /// Its light.
    pub light: LightLabel,
    /// Its place in the picture: corner x, y and side, in pixels.
    pub rect: [f32; 3],
    /// Its side in texels.
    pub texels: u32,
    /// The level of the virtual map's page it holds, if it holds one.
    pub level: Option<u32>,
}

/// GPU state that lives across frames: pipelines, meshes, shadow maps and the depth buffer.
pub struct Renderer {
    objects: UniformArray,
    joints: JointPalette,
    textures: MaterialTextures,
    meshes: Vec<Option<GpuMesh>>,
    shadow: ShadowPass,
    main: MainPass,
    depth: Option<DepthBuffer>,
    /// The user was told the SDSM fit cannot run here.
    sdsm_told: bool,
    /// The sample counts moment maps may be resolved from here (a bit per count: 2, 4, 8).
    sample_counts: u32,
    /// The moment samples last asked for that the device does not allow, once told.
    samples_told: Option<u32>,
    timer: Option<PassTimer>,
    /// The picture's format, and the light volumes' lines, made the first time they are shown.
    format: wgpu::TextureFormat,
    lines: Option<LinePass>,
    /// The shadow-map viewer, made the first time it is asked for, and the last picture's
    /// layers and whose they are.
    map_view: Option<MapView>,
    /// The bare depth pass the bench compares the shadow pass with, made when first asked for.
    bare: Option<BareDepth>,
    /// The camera's depth for contact shadows, made when first needed.
    camera_depth: Option<CameraDepth>,
    /// The depth reduction of the SDSM fit, made when first needed (where compute shaders run).
    reduction: Option<DepthReduction>,
    /// The marking of virtual pages, made when first needed (where compute shaders run).
    marking: Option<PageMarking>,
    /// The user was told virtual pages cannot be marked here.
    marks_told: bool,
    /// The device runs compute shaders.
    computes: bool,
    /// The moment formats the device makes in compute.
    compute_stores: ComputeStores,
    /// The adapter is a software rasterizer (where moments are resolved by full-screen passes
    /// unless the settings ask for compute; see [`crate::settings::MomentResolve`]).
    software: bool,
    /// Most draws a part of the main pass holds (0: it is drawn whole; see [`super::parts`]).
    part_draws: usize,
    last_layers: Vec<(GpuLayer, LightLabel, Option<u32>)>,
    /// A map was drawn or the layers changed since the viewer's atlas was last drawn.
    atlas_stale: bool,
    /// The lights last said to be lit without their shadow.
    shadowless: Vec<(LightLabel, Shadowless)>,
    /// What this device keeps of shadows per texel.
    caps: ShadowCaps,
    /// The culling hierarchy of the last frame's objects, to refit rather than build afresh.
    kept: KeptIndex,
    /// What the app has not heard yet.
    news: RenderNews,
}

impl Renderer {
    /// Builds the pipelines for a colour target of `format` (an sRGB format for correct output).
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Result<Renderer, RenderError> {
        let device = &gpu.device;
        let flags = gpu.adapter.get_downlevel_capabilities().flags;
        if !flags.contains(wgpu::DownlevelFlags::VERTEX_STORAGE) {
            return Err(RenderError::Unsupported(
                "storage buffers in vertex shaders, which GPU skinning reads joints from",
            ));
        }
        if !flags.contains(wgpu::DownlevelFlags::FRAGMENT_STORAGE) {
            return Err(RenderError::Unsupported(
                "storage buffers in fragment shaders, which the lighting reads every light from",
            ));
        }
        let objects = UniformArray::new(
            device,
            "objects",
            std::mem::size_of::<Object>() as u64,
            wgpu::ShaderStages::VERTEX_FRAGMENT,
        );
        let joints = JointPalette::new(device);
        let textures = MaterialTextures::new(device, &gpu.queue);
        let reads_depth = super::static_maps::reads_depth(&gpu.adapter);
        let computes = super::depth_reduction::computes(&gpu.adapter);
        let compute_stores = ComputeStores::of(&gpu.adapter, device);
        let shadow = ShadowPass::new(device, reads_depth, compute_stores, &objects.layout, &joints, &textures);
        let main = MainPass::new(device, &objects.layout, &joints, &textures, format, &shadow.maps);
        gpu.check_errors()?;
        let caps = ShadowCaps {
            full_float_moments: super::moments::full_supported(&gpu.adapter, gpu.device.features()),
            static_maps: reads_depth,
        };
        Ok(Renderer {
            objects,
            joints,
            textures,
            meshes: Vec::new(),
            shadow,
            main,
            depth: None,
            sdsm_told: false,
            sample_counts: super::moment_samples::sample_counts(&gpu.adapter, gpu.device.features()),
            samples_told: None,
            timer: None,
            format,
            lines: None,
            map_view: None,
            bare: None,
            camera_depth: None,
            reduction: None,
            marking: None,
            marks_told: false,
            computes,
            compute_stores,
            software: gpu.software(),
            part_draws: if gpu.software() { PART_DRAWS } else { 0 },
            last_layers: Vec::new(),
            atlas_stale: true,
            shadowless: Vec::new(),
            caps,
            kept: KeptIndex::default(),
            news: RenderNews { caps, ..RenderNews::default() },
        })
    }

    /// Renders the world as it is now into `target` (`width` x `height` pixels), drawing only the
    /// shadow maps that are dirty, and leaves what the shadow pass did in [`ShadowStats`].
    pub fn render(
        &mut self,
        gpu: &Gpu,
        world: &World,
        target: &wgpu::TextureView,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        self.draw(gpu, world, (width, height), Output::Picture(target))
    }

    /// Renders the measuring view of the world into `targets` (world position, normal, and the
    /// shadow visibility of lights `first_light` to `first_light + MEASURED_PER_PASS - 1`), with
    /// the same shadow maps and lighting code as [`Renderer::render`].
    pub fn render_debug(
        &mut self,
        gpu: &Gpu,
        world: &World,
        targets: &[wgpu::TextureView; 3],
        (width, height): (u32, u32),
        first_light: usize,
    ) -> Result<(), RenderError> {
        self.main.ensure_debug(&gpu.device, &self.joints, &self.textures);
        self.draw(gpu, world, (width, height), Output::Measure(targets, first_light))
    }

    /// Draws the shadow maps the world needs now, then makes the main pass's shadow tests of
    /// lights `first_light` to `first_light + MEASURED_PER_PASS - 1` at each of `points`
    /// (positions with unit normals) into `target`, a `grid`-sized integer target; the shader
    /// writes probe i to pixel (i % width, i / width).
    pub fn render_probes(
        &mut self,
        gpu: &Gpu,
        world: &World,
        (target, grid): (&wgpu::TextureView, (u32, u32)),
        (points, count): (&wgpu::Buffer, u32),
        first_light: usize,
    ) -> Result<(), RenderError> {
        self.draw(gpu, world, grid, Output::Probes(target, grid, points, count, first_light))
    }

    /// Draws the shadow maps the world needs now, then the camera's depth alone, `size`, and
    /// marks from it the virtual pages it needs and makes the SDSM fit's reduction: a frame that
    /// brings in what the view needs for less than a picture costs.
    pub fn render_priming(&mut self, gpu: &Gpu, world: &World, size: (u32, u32)) -> Result<(), RenderError> {
        self.draw(gpu, world, size, Output::Priming)
    }

    /// Draws the shadow maps the world needs now and nothing else (what `umbra bench
    /// --shadow-pass` times: the extract, culling and bookkeeping they take included).
    pub fn render_shadow_maps(&mut self, gpu: &Gpu, world: &World) -> Result<(), RenderError> {
        self.draw(gpu, world, (1, 1), Output::ShadowsOnly)
    }

    /// Draws `data`'s casters into its layers with the bare depth pass (see
    /// `render/bare_depth.rs`), in the tiles umbra's shadow pass gives them, of `depth`.
    pub fn render_bare_depth(
        &mut self,
        gpu: &Gpu,
        data: &super::FrameData,
        depth: crate::settings::ShadowDepth,
    ) -> Result<(), RenderError> {
        let format = super::shadow_atlas::depth_texture(depth);
        let mut data = data.clone();
        self.shadow.place(&mut data);
        if self.bare.as_ref().is_none_or(|b| b.format() != format) {
            self.bare = Some(BareDepth::new(&gpu.device, format));
        }
        let bare = self.bare.as_mut().expect("made above");
        let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("bare") });
        bare.encode((&gpu.device, &gpu.queue), &mut encoder, &data, &self.meshes, self.shadow.maps.shape);
        gpu.queue.submit([encoder.finish()]);
        gpu.check_errors()
    }

    /// The shadow-map viewer's picture of the atlas as the last frame used it, drawn again only
    /// when a map was drawn or the layers changed since; with whose each tile is and where.
    pub fn shadow_map_atlas(&mut self, gpu: &Gpu) -> MapAtlas<'_> {
        let view = self.map_view.get_or_insert_with(|| MapView::new(&gpu.device));
        if std::mem::take(&mut self.atlas_stale) || view.atlas().is_none() {
            let layers: Vec<GpuLayer> = self.last_layers.iter().map(|(l, ..)| *l).collect();
            let maps = (&self.shadow.maps.pages.array_view, &self.shadow.maps.moments.array_view);
            view.draw(&gpu.device, &gpu.queue, maps, &layers);
        }
        let (texture, atlas, generation) = view.atlas().expect("drawn above");
        let page = self.shadow.maps.shape.page as f32;
        let tiles = self.last_layers.iter().map(|(g, l, level)| AtlasTile {
            light: *l,
            rect: map_view::tile_rect(g),
            texels: (g.tile[2] * page).round() as u32,
            level: *level,
        });
        let pages = map_view::pages_of(&self.last_layers.iter().map(|(g, ..)| *g).collect::<Vec<_>>());
        MapAtlas { texture, view: atlas, generation, tiles: tiles.collect(), pages }
    }

    /// Draws the main pass in parts of at most `most` draws, each submitted and waited for
    /// before the next, and the shadow pass in parts four times as large, cut between tiles (0:
    /// whole; see `src/render/parts.rs`). A software adapter draws parts of [`crate::render::PART_DRAWS`]
    /// by default, so that what it bins ahead of drawing stays bounded; a GPU draws them whole.
    pub fn draw_in_parts(&mut self, most: usize) {
        self.part_draws = most;
    }

    /// Stamps every later frame's shadow and main passes with GPU timestamps, where the device
    /// can; false where it cannot (then time the frame on the CPU instead).
    pub fn enable_timing(&mut self, gpu: &Gpu) -> bool {
        self.timer = self.timer.take().or_else(|| PassTimer::new(gpu));
        self.timer.is_some()
    }

    /// The GPU time of the last frame's passes, if timing is on (waits for the GPU).
    pub fn pass_times(&mut self, gpu: &Gpu) -> Option<Result<PassTimes, RenderError>> {
        self.timer.as_mut().map(|t| t.read(gpu))
    }

    /// The GPU time of the passes of a frame or two ago, when it has come back, without waiting:
    /// for a live graph (call once a frame, after rendering).
    pub fn poll_pass_times(&mut self, gpu: &Gpu) -> Option<PassTimes> {
        self.timer.as_mut()?.poll(gpu)
    }

    /// Frees the shadow atlas's memory, keeping the pipelines: the next frame makes the atlas
    /// anew and draws every layer. For a holder of many scenes that draws one at a time (the
    /// failure cases of a sweep), so that only the one it draws holds an atlas.
    pub fn release_shadow_maps(&mut self, gpu: &Gpu) {
        let least = crate::shadow::AtlasShape { page: crate::shadow::MIN_TILE, pages: 1 };
        let depth = self.shadow.maps.depth;
        if self.shadow.ensure_maps(&gpu.device, least, moments::ColourLayout::NONE, depth) {
            self.main.rebind(&gpu.device, &self.shadow.maps);
        }
    }

    /// What the renderer learned since the app last heard from it (what this device keeps of
    /// shadows, the last frame's shadow pass, what the camera saw, messages for the user), for
    /// [`crate::App::hear`]. Hear it once the renderer is made, before the first frame, and after
    /// each frame.
    pub fn news(&mut self) -> RenderNews {
        std::mem::replace(&mut self.news, RenderNews { caps: self.caps, ..RenderNews::default() })
    }

    /// Waits for the depth reduction and the page marking under way, if any, and adds what they
    /// read back to the news.
    pub fn wait_for_samples(&mut self, gpu: &Gpu) {
        self.take_samples(gpu, true);
    }

    fn draw(
        &mut self,
        gpu: &Gpu,
        world: &World,
        (width, height): (u32, u32),
        output: Output<'_>,
    ) -> Result<(), RenderError> {
        let (device, queue) = (&gpu.device, &gpu.queue);
        if world.get_resource::<ShadowCaps>() != Some(&self.caps) {
            return Err(RenderError::NotTold);
        }
        let settings = FrameSettings::of(world).ok_or(RenderError::NoSettings)?;
        self.take_samples(gpu, false);
        // What this frame takes from the settings, read once (extraction borrows the world).
        let max = device.limits().max_texture_dimension_2d;
        if settings.maps.shadow_map_size > max {
            return Err(RenderError::ShadowMapTooLarge { size: settings.maps.shadow_map_size, max });
        }
        let mut how = DrawOptions::from(settings.maps);
        how.samples = self.usable_samples(how.samples);
        let (moment_bits, shadow_depth, shadows) =
            (settings.maps.moment_bits, settings.maps.shadow_depth, settings.shadow.enabled);
        let (sdsm, light_volumes) = (settings.cascade.fit_mode == FitMode::Sdsm, settings.view.light_volumes);
        let shape = match world.get_resource::<ShadowAtlas>() {
            Some(atlas) => atlas.shape,
            None => ShadowAtlas::for_settings(settings.maps, self.caps, std::iter::empty()).shape,
        };
        self.upload_new_meshes(device, world.resource::<MeshLibrary>());
        if let Some(library) = world.get_resource::<TextureLibrary>() {
            self.textures.upload_new(device, queue, library);
        }
        let depth = self.ensure_depth(device, width, height);
        // A frame of shadow maps alone leaves out what only the main pass reads.
        let lit = !matches!(output, Output::ShadowsOnly);
        let mut data = read_world(world, lit, &mut self.kept);
        let format = moments::colour_format(data.methods, moment_bits, gpu.full_float_moments())
            .map_err(RenderError::Unsupported)?;
        if let Some(format) = format {
            moments::set_terms(&mut data.layers, format);
        }
        if shape.page > max {
            return Err(RenderError::ShadowMapTooLarge { size: shape.page, max });
        }
        let storage = how.moments_from.from_depth()
            && settings.maps.moment_resolve.compute(self.software)
            && format.is_some_and(|f| self.compute_stores.stores(f.texture()));
        let colour =
            moments::ColourLayout { format, scale: moments::colour_scale(data.methods, how.moments_from), storage };
        if self.shadow.ensure_maps(device, shape, colour, shadow_depth) {
            self.main.rebind(device, &self.shadow.maps);
        }
        let update = world.get_resource::<crate::components::Time>().map(|t| t.updates);
        self.shadow.plan(&mut data, how, update);
        super::page_table::write_page_tables(&mut data);
        if lit {
            self.main.prepare((device, queue), &data, &self.shadow.maps)?;
            self.tell_shadowless(&data);
        }
        let objects: Vec<Object> = data.items.iter().map(|i| i.object).collect();
        self.objects.write(device, queue, &objects);
        self.joints.write(device, queue, &data.joints);

        let drawables =
            Drawables { meshes: &self.meshes, objects: &self.objects, joints: &self.joints, textures: &self.textures };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        if let Some(timer) = &mut self.timer {
            timer.begin();
        }
        let stats = if shadows {
            self.shadow.part_draws = self.part_draws.saturating_mul(SHADOW_PARTS_LARGER);
            self.shadow.encode((device, queue), &mut encoder, &data, drawables, how, self.timer.as_mut())?
        } else {
            ShadowStats::default()
        };
        self.atlas_stale |= stats.drawn() > 0 || stats.blurred() > 0;
        let (sees, priming) =
            (matches!(output, Output::Picture(_) | Output::Measure(..)), matches!(output, Output::Priming));
        if (data.frame.contact_steps > 0 && sees) || priming {
            let pass = self
                .camera_depth
                .get_or_insert_with(|| CameraDepth::new(device, &self.objects.layout, &self.joints, &self.textures));
            let timer = self.timer.as_mut();
            if let Some(view) = pass.encode((device, queue), &mut encoder, &data, drawables, (width, height), timer) {
                self.main.set_camera_depth(device, view, &self.shadow.maps);
            }
        }
        let timer = self.timer.as_ref();
        let reduces = sdsm && (sees || priming);
        let marks =
            shadows && (sees || priming) && data.lights.iter().any(|l| l.layer_count > 0 && l.light.pages.is_some());
        self.main.keep_depth = reduces || marks;
        // What the reduction and the marking read: the main pass's depth, or the camera's alone.
        let seen = match (priming, &self.depth, &self.camera_depth) {
            (true, _, Some(camera)) => camera.view().cloned(),
            (false, Some(depth), _) => Some(depth.depth_only.clone()),
            _ => None,
        };
        let parts = Part::split(data.draw_order.len(), self.part_draws);
        match output {
            Output::Picture(target) => {
                let whose = data.draws.iter().map(|d| (d.light, d.page.map(|p| p.level)));
                let layers: Vec<_> = data.layers.iter().copied().zip(whose).map(|(g, (l, p))| (g, l, p)).collect();
                if layers != self.last_layers {
                    (self.last_layers, self.atlas_stale) = (layers, true);
                }
                for part in &parts {
                    part.begin(gpu, &mut encoder)?;
                    self.main.encode(queue, &mut encoder, (target, &depth), &data, (drawables, timer, part));
                }
                if light_volumes {
                    let lines = self.lines.get_or_insert_with(|| LinePass::new(device, self.format));
                    let vertices = volume_lines(&data);
                    lines.encode(device, queue, &mut encoder, target, &data.clip_from_world, &vertices);
                }
            }
            Output::Measure(targets, first) => {
                data.measure_from(first);
                for part in &parts {
                    part.begin(gpu, &mut encoder)?;
                    self.main.encode_debug(queue, &mut encoder, (targets, &depth), &data, (drawables, timer, part));
                }
            }
            Output::Probes(target, (w, h), points, count, first) => {
                self.main.ensure_probe(device, data.methods);
                data.set_probe_grid(w, h);
                data.measure_from(first);
                self.main.encode_probes(queue, &mut encoder, target, &data, (points, count));
            }
            Output::ShadowsOnly | Output::Priming => {}
        }
        if let Some(seen) = seen.as_ref().map(|view| (view, (width, height))) {
            if reduces {
                self.reduce_depth(gpu, world, &mut encoder, &data, seen);
            }
            if marks {
                self.mark_pages(gpu, &mut encoder, &data, seen);
            }
        }
        if let Some(timer) = self.timer.as_mut() {
            timer.resolve(&mut encoder);
        }
        queue.submit([encoder.finish()]);
        self.news.stats = Some(stats);
        gpu.check_errors()
    }

    /// The moment samples a texel the device allows for `wanted`; says so once when fewer.
    fn usable_samples(&mut self, wanted: u32) -> u32 {
        let usable = super::moment_samples::usable(self.sample_counts, wanted);
        if usable != wanted && self.samples_told != Some(wanted) {
            self.samples_told = Some(wanted);
            let line =
                format!("moment maps resolved from {wanted} samples a texel are not allowed here: {usable} instead");
            self.news.notices.push(line);
        }
        usable
    }

    /// Says which shadowed lights are lit without their shadow and why, whenever that changes.
    fn tell_shadowless(&mut self, data: &FrameData) {
        if data.shadowless == self.shadowless {
            return;
        }
        self.shadowless = data.shadowless.clone();
        let mut why: Vec<Shadowless> = Vec::new();
        for (_, w) in &self.shadowless {
            if !why.contains(w) {
                why.push(*w);
            }
        }
        for reason in why {
            let names: Vec<String> =
                self.shadowless.iter().filter(|(_, w)| *w == reason).map(|(l, _)| l.to_string()).collect();
            let shown = names.iter().take(5).cloned().collect::<Vec<_>>().join(", ");
            let more = if names.len() > 5 { format!(" and {} more", names.len() - 5) } else { String::new() };
            let line = format!("{} lights are lit without their shadow ({shown}{more}): {reason}", names.len());
            self.news.notices.push(line);
        }
    }

    fn upload_new_meshes(&mut self, device: &wgpu::Device, library: &MeshLibrary) {
        for mesh in &library.all()[self.meshes.len().min(library.all().len())..] {
            self.meshes.push(GpuMesh::upload(device, mesh));
        }
    }

    /// The camera depth buffer for this size, re-created only when the size changes.
    fn ensure_depth(&mut self, device: &wgpu::Device, width: u32, height: u32) -> wgpu::TextureView {
        if let Some(d) = &self.depth
            && d.size == (width, height)
        {
            return d.view.clone();
        }
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.main.depth_format,
            // The SDSM reduction reads it.
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let depth_only = texture
            .create_view(&wgpu::TextureViewDescriptor { aspect: wgpu::TextureAspect::DepthOnly, ..Default::default() });
        self.depth = Some(DepthBuffer { view: view.clone(), depth_only, size: (width, height) });
        view
    }
}
