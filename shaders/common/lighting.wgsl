// Phong shading of one G-buffer sample by N point lights read from a 2D texture used as a 1D
// array (two texels a light: position + range, colour + intensity). Shared by the full-resolution
// deferred pass and every CPS level, so that level 0 reproduces full resolution bit for bit.

const BACKGROUND: vec3f = vec3f(0.02, 0.025, 0.035);

// Element `index` of a 2D texture of width `width` used as a 1D array: the exact integer
// addressing (the float variants lose exactness; see texarray.index_exactness).
fn array_texel(array: texture_2d<f32>, index: u32) -> vec4f {
    let width = textureDimensions(array).x;
    return textureLoad(array, vec2u(index % width, index / width), 0);
}

// `position.w` is 0 where no surface was drawn; `normal.w` the shininess; `albedo.w` the
// specular weight.
fn shade_sample(position: vec4f, normal: vec4f, albedo: vec4f, eye: vec3f, lights: texture_2d<f32>, light_count: u32) -> vec3f {
    if position.w == 0.0 {
        return BACKGROUND;
    }
    let n = normalize(normal.xyz);
    let to_eye = eye - position.xyz;
    let view_distance = length(to_eye);
    // A surface point at the eye has no view direction: look along the normal.
    let v = select(n, to_eye / view_distance, view_distance > 1e-6);
    var colour = albedo.rgb * 0.03;
    for (var i = 0u; i < light_count; i++) {
        let place = array_texel(lights, 2u * i);
        let tint = array_texel(lights, 2u * i + 1u);
        let to_light = place.xyz - position.xyz;
        let distance = length(to_light);
        let range = max(place.w, 1e-6);
        if distance >= range {
            continue;
        }
        // A light exactly at the surface point lights it head-on rather than dividing by zero.
        let l = select(n, to_light / distance, distance > 1e-6);
        let window = 1.0 - (distance / range) * (distance / range);
        let attenuation = window * window / (1.0 + distance * distance);
        let diffuse = max(dot(n, l), 0.0);
        let h = normalize(l + v);
        let specular = select(0.0, pow(max(dot(n, h), 0.0), normal.w), diffuse > 0.0);
        colour += tint.rgb * tint.w * attenuation * (albedo.rgb * diffuse + albedo.w * specular);
    }
    return colour;
}

// Shades the G-buffer sample at `pixel` (position f32 bits in an Rgba32Uint texture): the one
// code path full-resolution lighting and every CPS level share.
fn shade_gbuffer_pixel(
    position: texture_2d<u32>,
    normal: texture_2d<f32>,
    albedo: texture_2d<f32>,
    pixel: vec2u,
    eye: vec3f,
    lights: texture_2d<f32>,
    light_count: u32,
) -> vec3f {
    return shade_sample(
        bitcast<vec4f>(textureLoad(position, pixel, 0)),
        textureLoad(normal, pixel, 0),
        textureLoad(albedo, pixel, 0),
        eye,
        lights,
        light_count,
    );
}
