// Sorted alpha blending: premultiplied colour, blended "over" in back-to-front draw order.

@fragment
fn fs_sorted_blend(in: QuadVarying) -> @location(0) vec4f {
    let alpha = sanitized_alpha(in.alpha);
    return vec4f(in.colour * alpha, alpha);
}
