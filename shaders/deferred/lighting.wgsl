// Full-resolution deferred lighting: every pixel shaded from its own G-buffer sample. The
// reference CPS is measured against.

struct Shading {
    eye: vec3f,
    light_count: u32,
}

@group(0) @binding(0) var<uniform> shading: Shading;
@group(0) @binding(1) var gbuffer_position: texture_2d<u32>;
@group(0) @binding(2) var gbuffer_normal: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo: texture_2d<f32>;
@group(0) @binding(4) var lights: texture_2d<f32>;

@fragment
fn fs_deferred(@builtin(position) position: vec4f) -> @location(0) vec4f {
    let pixel = vec2u(position.xy);
    let colour = shade_gbuffer_pixel(gbuffer_position, gbuffer_normal, gbuffer_albedo, pixel, shading.eye, lights, shading.light_count);
    return vec4f(colour, 1.0);
}
