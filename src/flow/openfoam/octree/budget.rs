//! How many bytes an octree build may hold: the default bound derived from the mesh, and what
//! a blend sample and a tree entry take while building.

use super::{Datum, Lattice};
use crate::flow::openfoam::PolyMesh;

/// Most bytes an octree build may hold by default
/// ([`Options::max_bytes`](crate::flow::openfoam::octree::Options::max_bytes)), as a multiple of
/// the mesh's own bytes ([`default_max_bytes`]). A mesh takes about 290 bytes per cell (the
/// airway's 83 768 cells 24.5 MB: points, faces, owners, neighbours, face centres and areas,
/// cell centres and volumes). The tables measured on the airway take 0.4–4.9 kB per cell
/// (`paper-figures/fig18/NOTES.md`, History), and their build holds the blend's samples besides (about 175 bytes each, one
/// per lattice point of a leaf, against 128 bytes per tabulated node): at most 2.4 times the
/// table, 12 kB per cell. 64 times the mesh's bytes, about 19 kB per cell, holds that with room
/// to spare. A tolerance the budget cannot meet (1 000 leaves per cell) went on to 1.3–2.7 GiB
/// until killed; the refusal names the bytes it wanted.
pub const MESH_BYTES_MULTIPLE: usize = 64;
/// Least default bound on an octree build's bytes (64 MiB): a small mesh's table may take many
/// leaves per cell (its wall leaves, or a budget raised to resolve a front) at a memory no
/// machine is short of.
pub const MIN_BUILD_BYTES: usize = 64 << 20;

/// The default bound on an octree build's bytes for `mesh`
/// ([`Options::max_bytes`](crate::flow::openfoam::octree::Options::max_bytes) `None`):
/// [`MESH_BYTES_MULTIPLE`] times the mesh's own bytes, at least [`MIN_BUILD_BYTES`]. The mesh's
/// bytes: 24 per point, 4 per face vertex, 60 per face (its offset, owner, neighbour, centre
/// and area vector) and 32 per cell (its centre and volume).
pub fn default_max_bytes(mesh: &PolyMesh) -> usize {
    let vertices: usize = (0..mesh.n_faces()).map(|f| mesh.face(f).len()).sum();
    let own = mesh.points().len() * 24 + vertices * 4 + mesh.n_faces() * 60 + mesh.n_cells() * 32;
    own.saturating_mul(MESH_BYTES_MULTIPLE).max(MIN_BUILD_BYTES)
}

/// Bytes a blend sample takes in the build's map: its lattice point and datum, one control
/// byte, and the map's spare room (at most 1/8 of it free when full).
pub(super) const SAMPLE_BYTES: usize = (size_of::<(Lattice, Datum)>() + 1) * 8 / 7;
/// Bytes a tree entry takes in the build: the entry, its level and its lattice corner.
pub(super) const ENTRY_BYTES: usize = size_of::<u32>() * 2 + size_of::<Lattice>();
