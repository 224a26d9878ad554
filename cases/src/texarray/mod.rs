//! `texarray.*`: 2D textures used as 1D arrays (how the CPS lights are stored).

fragkit::cases! {
    index_exactness: CASE;
}
