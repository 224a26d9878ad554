// Axis-aligned rectangles given per instance in clip space (x0, y0, x1, y1), two triangles each.
// The kit's probes draw stencil patterns, coverage edges and fills with it.

struct RectInstance {
    @location(0) rect: vec4f,
    @location(1) colour: vec4f,
}

struct RectVarying {
    @builtin(position) position: vec4f,
    @location(0) colour: vec4f,
}

@vertex
fn vs_rect(@builtin(vertex_index) vertex_index: u32, instance: RectInstance) -> RectVarying {
    // Corners of the two triangles (0,1,2) (2,1,3) of the quad, as (use x1?, use y1?).
    var corners = array<vec2u, 6>(vec2u(0u, 0u), vec2u(1u, 0u), vec2u(0u, 1u), vec2u(0u, 1u), vec2u(1u, 0u), vec2u(1u, 1u));
    let corner = corners[vertex_index];
    let x = select(instance.rect.x, instance.rect.z, corner.x == 1u);
    let y = select(instance.rect.y, instance.rect.w, corner.y == 1u);
    return RectVarying(vec4f(x, y, 0.0, 1.0), instance.colour);
}

@fragment
fn fs_instance_colour(in: RectVarying) -> @location(0) vec4f {
    return in.colour;
}
