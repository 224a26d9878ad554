// Weighted blended OIT (McGuire & Bavoil 2013), accumulation: premultiplied colour and alpha
// scaled by a depth weight into an additive target, and the product of (1 - alpha) into the
// revealage target. Equation (9) of the paper's weight functions.

struct WeightedTargets {
    @location(0) accumulation: vec4f,
    @location(1) revealage: vec4f,
}

@fragment
fn fs_weighted_accumulate(in: QuadVarying) -> WeightedTargets {
    let alpha = sanitized_alpha(in.alpha);
    let z = in.position.z;
    let weight = clamp(alpha * max(1e-2, 3e3 * pow(1.0 - z, 3.0)), 1e-2, 3e3);
    return WeightedTargets(vec4f(in.colour * alpha, alpha) * weight, vec4f(alpha));
}
