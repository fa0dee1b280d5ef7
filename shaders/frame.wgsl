// What the main pass knows of the frame: the camera, the settings that shape shadows, every
// light and every shadow-map layer (bind group 0). The layouts are checked against the Rust
// structs of the same names (src/render/extract.rs) by a test.

struct Frame {
    clip_from_world: mat4x4<f32>,
    camera_position: vec3<f32>,
    // Beyond this view depth suns cast no shadow.
    shadow_distance: f32,
    camera_forward: vec3<f32>,
    // View depth where sun shadows start to fade out.
    fade_start: f32,
    ambient: f32,
    shadow_strength: f32,
    shadows_on: u32,
    cascade_debug: u32,
    light_count: u32,
    // The measuring view reports lights first_measured .. first_measured + MEASURED_PER_PASS.
    first_measured: u32,
    // Probes are drawn into a grid this many pixels wide and high.
    probe_width: u32,
    probe_height: u32,
    // 1 when the seams of shadow cubes are handled (see cube_test in lights.wgsl).
    cube_seams: u32,
    // Depth bias in metres along the light, on top of every light's own (in texels).
    depth_bias_metres: f32,
    // 1 when PCSS searches for blockers (else it filters with a fixed kernel).
    pcss_search: u32,
    // Bands of toon shading (0: Phong; see toon in main.wgsl).
    toon_bands: u32,
    // 1 + the index of the light whose shadow-map texel density is shown instead of the
    // shading (0: the shading; see texel_density in main.wgsl).
    texel_view: u32,
    // The view depths the slices of light clusters span (see lights_at in lights.wgsl).
    cluster_near: f32,
    cluster_far: f32,
    // 1 when lookups keep their taps inside their own tile (see atlas_uv in shadow_sampling.wgsl).
    atlas_guard: u32,
    // The contact-shadow march (see contact.wgsl): its steps (0: none this frame), its length
    // and the thickness surfaces are taken to have, in metres.
    contact_steps: u32,
    contact_length: f32,
    contact_thickness: f32,
    // The camera's near and far planes (contact shadows turn its depth back into distance).
    camera_near: f32,
    camera_far: f32,
    // Radians a pixel of the picture spans (at its middle; see page_level in pages.wgsl).
    pixel_angle: f32,
    // 1 when a pixel whose virtual page is missing reads a coarser level or the coarse map
    // (else it reads as lit; see page_layer in pages.wgsl).
    page_fallback: u32,
    _pad2: u32,
};

// One light; `kind` is LIGHT_SUN, LIGHT_SPOT or LIGHT_POINT, `shape` SHAPE_CASCADES, SHAPE_SINGLE,
// SHAPE_CUBE or SHAPE_PAGES.
struct GpuLight {
    // Colour times intensity.
    color: vec3<f32>,
    kind: u32,
    position: vec3<f32>,
    range: f32,
    // Unit direction the light travels (suns) or shines (spots).
    direction: vec3<f32>,
    cos_outer: f32,
    cos_inner: f32,
    // Its layers: first_layer .. first_layer + layer_count (none when layer_count is 0).
    first_layer: u32,
    layer_count: u32,
    // Cookie layer, or -1 for none.
    cookie: i32,
    // Biases in texels.
    bias_constant: f32,
    bias_slope: f32,
    bias_normal: f32,
    // METHOD_* it is sampled with.
    method: u32,
    // SHAPE_CASCADES, SHAPE_SINGLE, SHAPE_CUBE or SHAPE_PAGES.
    shape: u32,
    // Size for soft shadows: tan of a sun's angular radius, or a spot or point light's radius.
    size: f32,
    // Multiplicative depth offset: the share of the distance to the light the receiver is
    // pulled towards it before the test (see scaled_depth in shadow_sampling.wgsl).
    bias_scale: f32,
    // 1 when it draws planar shadows onto the ground in place of its maps there.
    planar_ground: u32,
    // 1 when its filters compare each tap with the receiver's plane (see receiver_plane in
    // shadow_sampling.wgsl).
    receiver_plane: u32,
    // 1 when its shadow test adds a contact-shadow march (see contact.wgsl).
    contact: u32,
    // 1 when a paged light's shadow ends at the shadow distance (a sun's clipmap).
    page_fades: u32,
    // 6 for a point light's cube of pages (its face matrices in its page table), else 1.
    page_faces: u32,
    // The cookie's projection (spots with a cookie only).
    cookie_from_world: mat4x4<f32>,
    // A paged light's virtual map (see pages.wgsl): world to level-0 page units (over w), its
    // levels (0: not paged), its page table's first word, log2 of its finest texel in metres
    // where w is 1 and the octaves coarser a pixel's page is chosen.
    page_from_world: mat4x4<f32>,
    page_levels: u32,
    page_word: u32,
    page_finest_log2: f32,
    page_bias: f32,
    // How near to a paged light its casters come along its axis (metres; 0: not measured).
    nearest_caster: f32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(0) @binding(0) var<uniform> frame: Frame;
// Cookie images, COOKIE_SIZE² bytes each, four bytes to a word, sixteen to an element.
@group(0) @binding(3) var<uniform> cookies: array<vec4<u32>, COOKIE_VECTORS>;
@group(0) @binding(4) var<storage, read> lights: array<GpuLight>;
@group(0) @binding(5) var<storage, read> layers: array<GpuLayer>;
// The clustered light lists (src/light/clusters.rs): for each cluster, where its entries start
// and how many it has (two words a cluster), then the light indices, cluster after cluster, in
// rows of LIST_WIDTH words of an integer texture (read with list_word in lights.wgsl).
@group(0) @binding(9) var cluster_lists: texture_2d<u32>;
// The page tables of paged lights (src/render/page_table.rs), in rows of LIST_WIDTH words of an
// integer texture (read with table_word in pages.wgsl).
@group(0) @binding(11) var page_tables: texture_2d<u32>;
