// Checkerboard reconstruction: one full-resolution fragment pass over frames N and N−1 in the
// sample layout. A pixel frame N sampled is read directly; any other is looked up in frame N−1
// through its motion (per-object motion where an object moves, else the camera's, from depth
// and the previous view-projection), unless the lookup lands on frame N's own pixels (motion
// cancelling the jitter), leaves the screen, finds stale history, or — after moving at least a
// quarter-resolution pixel — fails the depth check (CSO) or is assumed missing (ASO); missing
// shading is filled from the four cardinal neighbours through a reversible tonemap. The second
// output classifies every pixel (see `PixelSource` in kit/src/cbr/reconstruct.rs); a third, for
// pictures only (`fs_reconstruct_showing_motion`), holds the motion each pixel used.

struct Reconstruction {
    world_from_clip: mat4x4f,
    previous_full_from_world: mat4x4f,
    screen: vec2i,
    quarter: vec2i,
    phase: i32,
    // 1 where frame N−1 exists.
    has_history: u32,
    depth_tolerance: f32,
    near: f32,
    far: f32,
}

// What the renderer's plan says the scene can need (kit/src/cbr/plan.rs), fixed per pipeline:
// the work a scene cannot need is compiled out, not skipped at run time — a CPU rasteriser runs
// both sides of a branch its lanes disagree on, and a branch on a buffer value in both.
override camera_moves: bool;
override objects_move: bool;
override forward_buffer: bool;
// CSO's depth check, else ASO.
override depth_check: bool;

const FROM_CURRENT: u32 = 0u;
const FROM_HISTORY: u32 = 1u;
const FILLED_FIRST_FRAME: u32 = 2u;
const FILLED_JITTER_CANCELLED: u32 = 3u;
const FILLED_DISOCCLUDED: u32 = 4u;
const FILLED_ASSUMED: u32 = 5u;
const FILLED_OFF_SCREEN: u32 = 6u;

// A quarter-resolution pixel is two full-resolution pixels wide.
const QUARTER_PIXEL: f32 = 2.0;

// The per-frame parameters are a read-only storage buffer, not a uniform: lavapipe specialises
// a shader on uniform values that decide branches (the phase, the history) and, with values that
// change every frame, kept every variant (1.6 MB a frame, measured by soak.cbr). Where fragment
// shaders have no storage buffers (GL 3.3), the renderer declares it `var<uniform>` instead
// (`ParameterBuffer` in kit/src/cbr/reconstruct.rs): the struct's layout is the same. Depth buffers are
// bound as unfilterable float (`.r`): naga's GLSL output has no textureLoad on depth textures.
@group(0) @binding(0) var<storage, read> rebuild: Reconstruction;
@group(0) @binding(1) var current_colour: texture_2d<f32>;
@group(0) @binding(2) var current_depth: texture_2d<f32>;
@group(0) @binding(3) var current_motion: texture_2d<f32>;
@group(0) @binding(4) var current_forward: texture_2d<f32>;
@group(0) @binding(5) var previous_colour: texture_2d<f32>;
@group(0) @binding(6) var previous_depth: texture_2d<f32>;
@group(0) @binding(7) var previous_motion: texture_2d<f32>;
@group(0) @binding(8) var previous_forward: texture_2d<f32>;

struct Rebuilt {
    colour: vec3f,
    source: u32,
    motion: vec2f,
}

fn on_screen(p: vec2i) -> bool {
    return all(p >= vec2i(0)) && all(p < rebuild.screen);
}

// A frame's colour at a layout texel: the shaded sample, under the forward buffer's
// transparent objects where the deferred path has them.
fn frame_sample(colour: texture_2d<f32>, forward: texture_2d<f32>, texel: vec2i) -> vec3f {
    let shaded = textureLoad(colour, texel, 0).rgb;
    if !forward_buffer {
        return shaded;
    }
    let over = textureLoad(forward, texel, 0);
    return shaded * (1.0 - over.a) + over.rgb;
}

fn current_sample(texel: vec2i) -> vec3f {
    return frame_sample(current_colour, current_forward, texel);
}

fn rebuilt(colour: vec3f, source: u32) -> Rebuilt {
    return Rebuilt(colour, source, vec2f(0.0));
}

// A pixel lying within this distance of the edge between two pixels' centres may take either
// (half-pixel motion lands exactly there; rounding must not decide between history and a fill).
const EDGE_SLACK: f32 = 1.0 / 64.0;

// The frame N−1 sample nearest to `before`: the pixel it lies in when N−1 sampled that one,
// else a neighbour of it whose centre is within half a pixel (plus slack) on both axes.
fn history_texel(before: vec2f) -> vec2i {
    let was = vec2i(floor(before));
    let direct = checkerboard_texel(was, 1 - rebuild.phase, rebuild.quarter);
    if direct.x >= 0 {
        return direct;
    }
    let steps = array<vec2i, 4>(vec2i(-1, 0), vec2i(1, 0), vec2i(0, -1), vec2i(0, 1));
    for (var i = 0; i < 4; i++) {
        let candidate = was + steps[i];
        let offset = abs(vec2f(candidate) + 0.5 - before);
        if all(offset <= vec2f(0.5 + EDGE_SLACK)) && on_screen(candidate) {
            let texel = checkerboard_texel(candidate, 1 - rebuild.phase, rebuild.quarter);
            if texel.x >= 0 {
                return texel;
            }
        }
    }
    return vec2i(-1);
}

struct Reconstructed {
    @location(0) colour: vec4f,
    @location(1) source: u32,
}

@fragment
fn fs_reconstruct(@builtin(position) position: vec4f) -> Reconstructed {
    let pixel = reconstruct(vec2i(position.xy));
    return Reconstructed(vec4f(pixel.colour, 1.0), pixel.source);
}

// A still scene's frame with history (the plan says nothing moves): every pixel frame N did not
// sample, frame N−1 did at the same place — but column 0's odd rows, which neither phase samples
// and fs_reconstruct fills (the renderer scissors this entry point to x ≥ 1). The same colours and
// sources as fs_reconstruct there, without computing a fill no pixel uses.
@fragment
fn fs_reconstruct_still(@builtin(position) position: vec4f) -> Reconstructed {
    let p = vec2i(position.xy);
    let own = checkerboard_texel(p, rebuild.phase, rebuild.quarter);
    if own.x >= 0 {
        return Reconstructed(vec4f(current_sample(own), 1.0), FROM_CURRENT);
    }
    let history = checkerboard_texel(p, 1 - rebuild.phase, rebuild.quarter);
    return Reconstructed(vec4f(frame_sample(previous_colour, previous_forward, history), 1.0), FROM_HISTORY);
}

struct ReconstructedWithMotion {
    @location(0) colour: vec4f,
    @location(1) source: u32,
    @location(2) motion: vec4f,
}

@fragment
fn fs_reconstruct_showing_motion(@builtin(position) position: vec4f) -> ReconstructedWithMotion {
    let pixel = reconstruct(vec2i(position.xy));
    return ReconstructedWithMotion(vec4f(pixel.colour, 1.0), pixel.source, vec4f(pixel.motion, 0.0, 1.0));
}

fn reconstruct(p: vec2i) -> Rebuilt {
    let phase = rebuild.phase;
    let own = checkerboard_texel(p, phase, rebuild.quarter);
    if own.x >= 0 {
        return rebuilt(current_sample(own), FROM_CURRENT);
    }

    // The cardinal neighbours are frame N's pixels: the fill, and where anything can move, their
    // mean linear depth and the frontmost one, whose depth and motion stand in for this pixel's.
    var fill_sum = vec3f(0.0);
    var depth_sum = 0.0;
    var count = 0.0;
    var front_depth = 2.0;
    var front_texel = vec2i(-1);
    let steps = array<vec2i, 4>(vec2i(-1, 0), vec2i(1, 0), vec2i(0, -1), vec2i(0, 1));
    for (var i = 0; i < 4; i++) {
        let neighbour = p + steps[i];
        if !on_screen(neighbour) {
            continue;
        }
        let texel = checkerboard_texel(neighbour, phase, rebuild.quarter);
        if texel.x < 0 {
            continue;
        }
        fill_sum += compress_hdr(current_sample(texel));
        count += 1.0;
        if camera_moves || objects_move {
            let depth = textureLoad(current_depth, texel, 0).r;
            depth_sum += linear_depth(depth, rebuild.near, rebuild.far);
            if depth < front_depth {
                front_depth = depth;
                front_texel = texel;
            }
        }
    }
    if count == 0.0 {
        return rebuilt(BACKGROUND, FILLED_OFF_SCREEN);
    }
    let fill = expand_hdr(fill_sum / count);
    if rebuild.has_history == 0u {
        return rebuilt(fill, FILLED_FIRST_FRAME);
    }

    let centre = vec2f(p) + 0.5;
    var motion = vec2f(0.0);
    var moving_object = false;
    if objects_move {
        let object = textureLoad(current_motion, front_texel, 0);
        moving_object = object.a > 0.0;
        motion = object.xy;
    }
    if !moving_object && camera_moves {
        let world = unproject(centre, front_depth, vec2f(rebuild.screen), rebuild.world_from_clip);
        motion = centre - project_to_pixels(world, rebuild.previous_full_from_world, vec2f(rebuild.screen));
    }
    var pixel = missing(centre, fill, motion, depth_sum / count, moving_object);
    pixel.motion = motion;
    return pixel;
}

// Pixel centre `centre`, which frame N did not sample, whose content moved by `motion` since
// frame N−1: its history, or the fill where there is none to trust.
fn missing(centre: vec2f, fill: vec3f, motion: vec2f, mean_depth: f32, moving_object: bool) -> Rebuilt {
    let before = centre - motion;
    // Motion past the screen (or not finite) has no history.
    if !(all(before >= vec2f(0.0)) && all(before < vec2f(rebuild.screen))) {
        return rebuilt(fill, FILLED_OFF_SCREEN);
    }
    let history = history_texel(before);
    if history.x < 0 {
        // Frame N−1 has no sample there: it is one of frame N's own pixels (the motion cancelled
        // the jitter), or the documented gap column.
        let cancelled = checkerboard_texel(vec2i(floor(before)), rebuild.phase, rebuild.quarter).x >= 0;
        return rebuilt(fill, select(FILLED_OFF_SCREEN, FILLED_JITTER_CANCELLED, cancelled));
    }
    // History that moved with an object where this pixel does not (or the reverse) is stale:
    // what it showed has left.
    if objects_move && (textureLoad(previous_motion, history, 0).a > 0.0) != moving_object {
        return rebuilt(fill, FILLED_DISOCCLUDED);
    }
    if length(motion) >= QUARTER_PIXEL - EDGE_SLACK {
        if !depth_check {
            return rebuilt(fill, FILLED_ASSUMED);
        }
        let then = linear_depth(textureLoad(previous_depth, history, 0).r, rebuild.near, rebuild.far);
        if abs(then - mean_depth) > rebuild.depth_tolerance * mean_depth {
            return rebuilt(fill, FILLED_DISOCCLUDED);
        }
    }
    return rebuilt(frame_sample(previous_colour, previous_forward, history), FROM_HISTORY);
}
