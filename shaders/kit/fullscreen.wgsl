// The vertex stage of every full-screen pass: one triangle covering the target. Fragment stages
// live in their own pass files and read only @builtin(position).

@vertex
fn vs_fullscreen(@builtin(vertex_index) vertex_index: u32) -> @builtin(position) vec4f {
    return fullscreen_clip_position(vertex_index);
}
