// PCG hash (Jarzynski & Olano 2020); kit/src/scene/hash.rs implements the same function, so CPU
// expectations and GPU results draw the same numbers.
fn pcg_hash(input: u32) -> u32 {
    let state = input * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A uniform number in [0, 1) with 24 bits, exactly representable in f32.
fn hash_unit(input: u32) -> f32 {
    return f32(pcg_hash(input) >> 8u) * (1.0 / 16777216.0);
}
