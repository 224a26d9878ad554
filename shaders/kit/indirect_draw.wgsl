// The indirect-draw probe's fragment stage (vertex: kit/fullscreen.wgsl): a constant colour, so a
// pixel that is not this colour was never drawn.

@fragment
fn fs_indirect_draw() -> @location(0) vec4f {
    return vec4f(0.0, 1.0, 0.0, 1.0);
}
