//! CPU references for the CPS composites (filled in below).
