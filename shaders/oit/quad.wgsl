// Vertex stage of every OIT pass: quads given per instance as a clip-space rect, a depth at the
// left and right edges (equal for the flat transparent layers, different for a tilted opaque
// object), an opacity, a colour and a key: the quad's identity whatever order it is drawn in. The
// key breaks depth ties and seeds the per-fragment random number, so results do not depend on
// draw order.

struct QuadInstance {
    @location(0) rect: vec4f,
    @location(1) depth_alpha: vec3f,
    @location(2) colour: vec3f,
    @location(3) key: u32,
}

@vertex
fn vs_quad(@builtin(vertex_index) vertex_index: u32, quad: QuadInstance) -> QuadVarying {
    var corners = array<vec2u, 6>(vec2u(0u, 0u), vec2u(1u, 0u), vec2u(0u, 1u), vec2u(0u, 1u), vec2u(1u, 0u), vec2u(1u, 1u));
    let corner = corners[vertex_index];
    let x = select(quad.rect.x, quad.rect.z, corner.x == 1u);
    let y = select(quad.rect.y, quad.rect.w, corner.y == 1u);
    let depth = select(quad.depth_alpha.x, quad.depth_alpha.y, corner.x == 1u);
    return QuadVarying(vec4f(x, y, depth, 1.0), quad.colour, quad.depth_alpha.z, quad.key);
}
