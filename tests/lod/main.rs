//! The quadtree LOD (thesis section 5): culling, geomorphing, watertightness, and `vr-ocean lod`.

#[path = "../common/mod.rs"]
mod common;

mod cli;
mod culling;
mod geomorph;
mod watertight;
