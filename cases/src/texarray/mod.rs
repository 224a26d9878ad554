//! `texarray.*`: 2D textures used as 1D arrays (how the CPS lights are stored).

pub mod index_exactness;
