// Checkerboard rendering's shared arithmetic. Sample layout: each of a frame's two samples per
// quarter-resolution pixel in its half of a (2·Hq)×Wq texture, the Wq×Hq view turned a quarter
// (kit/src/cbr/sampling.rs, QUARTER_TURN): sample s of quarter pixel q at (q.y + s·Hq, Wq − 1 − q.x).
// Phase j (the frame's jitter, 0 or 1) samples full-resolution pixel p when p.x + p.y + j is even:
// an even row through sample 1 of q = ((x − j)/2, y/2), an odd row through sample 0 of
// q = ((x − 1 − j)/2, (y − 1)/2).

// The layout texel holding pixel `p` in phase `phase`, or (-1, -1) where that phase has no sample
// of it (the other phase's pixels, and the documented gap: odd rows of column 0 in phase 1).
fn checkerboard_texel(p: vec2i, phase: i32, quarter: vec2i) -> vec2i {
    if ((p.x + p.y + phase) & 1) != 0 {
        return vec2i(-1);
    }
    let odd_row = p.y & 1;
    let q = vec2i((p.x - odd_row - phase) >> 1u, p.y >> 1u);
    if any(q < vec2i(0)) || any(q >= quarter) {
        return vec2i(-1);
    }
    return vec2i(q.y + (1 - odd_row) * quarter.y, quarter.x - 1 - q.x);
}

// The quarter pixel and sample index a layout texel holds.
fn layout_sample(texel: vec2i, quarter: vec2i) -> vec3i {
    let sample = select(0, 1, texel.x >= quarter.y);
    return vec3i(quarter.x - 1 - texel.y, texel.x - sample * quarter.y, sample);
}

// The full-resolution pixel centre the layout texel's sample sees in phase `phase` (standard 2x
// positions: sample 0 at (0.75, 0.75), sample 1 at (0.25, 0.25) of its quarter pixel).
fn layout_pixel_centre(texel: vec2i, quarter: vec2i, phase: i32) -> vec2f {
    let at = layout_sample(texel, quarter);
    let offset = select(vec2f(1.5), vec2f(0.5), at.z == 1);
    return 2.0 * vec2f(at.xy) + offset + vec2f(f32(phase), 0.0);
}

// The world position of a full-resolution pixel centre at depth-buffer value `depth`.
fn unproject(centre: vec2f, depth: f32, screen: vec2f, world_from_clip: mat4x4f) -> vec3f {
    let ndc = vec3f(centre.x / screen.x * 2.0 - 1.0, 1.0 - centre.y / screen.y * 2.0, depth);
    let world = world_from_clip * vec4f(ndc, 1.0);
    return world.xyz / world.w;
}

// Where a world point lands on the full-resolution screen, in pixels.
fn project_to_pixels(world: vec3f, clip_from_world: mat4x4f, screen: vec2f) -> vec2f {
    let clip = clip_from_world * vec4f(world, 1.0);
    let ndc = clip.xy / clip.w;
    return vec2f((ndc.x + 1.0) * 0.5 * screen.x, (1.0 - ndc.y) * 0.5 * screen.y);
}

// Distance along the view axis from a [0, 1] depth-buffer value of a right-handed perspective.
fn linear_depth(depth: f32, near: f32, far: f32) -> f32 {
    return near * far / (far - depth * (far - near));
}

// A reversible tonemap: blending through it keeps one bright sample from dominating a fill.
fn compress_hdr(colour: vec3f) -> vec3f {
    return colour / (1.0 + max(colour.r, max(colour.g, colour.b)));
}

fn expand_hdr(colour: vec3f) -> vec3f {
    return colour / max(1.0 - max(colour.r, max(colour.g, colour.b)), 1e-4);
}

// One G-buffer sample's colour: unlit flat colour where the shininess is negative, the
// background where nothing was drawn (zero normal), Phong otherwise.
fn shade_checkerboard_sample(
    normal: vec4f,
    albedo: vec4f,
    world: vec3f,
    eye: vec3f,
    lights: texture_2d<f32>,
    light_count: u32,
) -> vec3f {
    if dot(normal.xyz, normal.xyz) == 0.0 {
        return BACKGROUND;
    }
    if normal.w < 0.0 {
        return albedo.rgb;
    }
    return shade_sample(vec4f(world, 1.0), normal, albedo, eye, lights, light_count);
}

// The deferred shade passes' per-frame parameters.
struct SampleShading {
    world_from_clip: mat4x4f,
    screen: vec2f,
    quarter: vec2i,
    eye: vec3f,
    light_count: u32,
    phase: i32,
}

// The colour of a G-buffer sample taken at full-resolution position `centre` (pixels), its world
// position from depth.
fn shade_at(
    shading: SampleShading,
    centre: vec2f,
    normal: vec4f,
    albedo: vec4f,
    depth: f32,
    lights: texture_2d<f32>,
) -> vec4f {
    let world = unproject(centre, depth, shading.screen, shading.world_from_clip);
    return vec4f(shade_checkerboard_sample(normal, albedo, world, shading.eye, lights, shading.light_count), 1.0);
}

// The colour of the G-buffer sample a shade-resolve texel holds.
fn shade_layout_texel(
    shading: SampleShading,
    texel: vec2i,
    normal: vec4f,
    albedo: vec4f,
    depth: f32,
    lights: texture_2d<f32>,
) -> vec4f {
    return shade_at(shading, layout_pixel_centre(texel, shading.quarter, shading.phase), normal, albedo, depth, lights);
}
