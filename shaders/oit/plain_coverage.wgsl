// Plain alpha-to-coverage: alpha a straight to the coverage unit. Equal alphas pick the same
// samples, so equal-opacity layers erase each other (the failure stochastic transparency fixes).

@fragment
fn fs_plain_coverage(in: QuadVarying) -> @location(0) vec4f {
    return vec4f(in.colour, sanitized_alpha(in.alpha));
}
