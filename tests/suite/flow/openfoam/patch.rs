//! Patch types as OpenFOAM writes them: a 2-D case's `empty` patches read (the fixture
//! `tests/data/channel-2d`, as simpleFoam wrote it); every other type a particle can meet
//! refused by name.

use crate::common::build;
use build::{channel_2d, channel_copy, retype};
use pseudorigid::flow::openfoam::{FoamCase, FoamError, PatchRole, check_particle_patches};

/// The 2-D channel: `phi`'s `frontAndBack` is `value nonuniform 0();` and `U`'s is
/// `type empty;` with no value, as simpleFoam writes them. Checked against the case's own
/// numbers, not the reader's earlier output: the inlet carries U_in·A = 0.1 m/s × 2 mm × 0.5 mm
/// = 10⁻⁷ m³/s in (negative: phi is positive out of the domain), the outlet the same out
/// (continuity; simpleFoam's converged `consistent` SIMPLE balances it to its residual, 10⁻⁶ of
/// the flux), the empty patch none, and U on the empty faces is the cell's.
#[test]
fn a_two_d_case_reads_as_openfoam_writes_it() {
    let case = FoamCase::open(channel_2d()).unwrap();
    let mesh = case.mesh();
    let flux = case.read_boundary_flux(117.0).unwrap().expect("the case has phi");
    let patch_flux = |name: &str| {
        let p = mesh.patches().iter().find(|p| p.name == name).unwrap();
        let b = p.start - mesh.n_internal_faces();
        flux[b..b + p.size].iter().sum::<f64>()
    };
    let q = 0.1 * 2e-3 * 0.5e-3;
    assert!(
        (patch_flux("inlet") + q).abs() <= 1e-12 * q,
        "inlet {}",
        patch_flux("inlet")
    );
    assert!(
        (patch_flux("outlet") - q).abs() <= 1e-6 * q,
        "outlet {}",
        patch_flux("outlet")
    );
    assert_eq!(patch_flux("frontAndBack"), 0.0);
    let u = case.read_field(117.0, "U", 3).unwrap();
    let empty = mesh.patches().iter().find(|p| p.kind == "empty").unwrap();
    assert_eq!(empty.size, 80);
    for f in empty.start..empty.start + empty.size {
        assert_eq!(u.boundary_face(f - mesh.n_internal_faces()), u.cell(mesh.owner(f)));
    }
}

/// The empty list is accepted on `empty` patches only: on a wall of 20 faces it is refused as
/// before, with the patch named.
#[test]
fn an_empty_list_elsewhere_is_refused() {
    let dir = channel_copy("empty_list_on_a_wall");
    let phi = std::fs::read_to_string(dir.join("117/phi")).unwrap();
    let at = phi.find("    walls").unwrap();
    let end = at + phi[at..].find('}').unwrap();
    let walls = "    walls\n    {\n        type calculated;\n        value nonuniform 0();\n    ";
    std::fs::write(dir.join("117/phi"), format!("{}{walls}{}", &phi[..at], &phi[end..])).unwrap();
    let case = FoamCase::open(&dir).unwrap();
    let err = case.read_boundary_flux(117.0).unwrap_err();
    assert!(matches!(err, FoamError::Field { .. }), "{err}");
    let message = err.to_string();
    assert!(
        message.contains("walls") && message.contains("an empty list for 20 faces"),
        "{message}"
    );
}

/// Every patch type: `wall`, `patch`, `empty`, `processor` and the types particles pass through
/// (`cyclic`, `cyclicAMI`, `symmetry`, `symmetryPlane`, `wedge`) are particle boundaries with
/// their roles; every other type OpenFOAM has (and one it has not) is refused with the patch,
/// its type and its faces named, whichever patch carries it (the 80 faces of `frontAndBack`,
/// the 20 of `walls`).
#[test]
fn every_patch_type_is_handled_or_refused_by_name() {
    let handled = [
        ("wall", PatchRole::Wall),
        ("patch", PatchRole::Exit),
        ("empty", PatchRole::Constraint),
        ("processor", PatchRole::Constraint),
        ("symmetry", PatchRole::Image),
        ("symmetryPlane", PatchRole::Image),
    ];
    for (kind, role) in handled {
        assert_eq!(PatchRole::of_particle_boundary(kind), Some(role), "{kind}");
        let dir = channel_copy(&format!("handled_{kind}"));
        retype(&dir, "frontAndBack", kind);
        check_particle_patches(FoamCase::open(&dir).unwrap().mesh()).unwrap();
    }
    // Pairs need their partner in the boundary file (`tests/suite/flow/openfoam/images.rs`).
    for kind in ["cyclic", "cyclicAMI", "wedge"] {
        assert_eq!(PatchRole::of_particle_boundary(kind), Some(PatchRole::Image), "{kind}");
    }
    let refused = [
        "cyclicACMI",
        "cyclicSlip",
        "mappedPatch",
        "mappedWall",
        "processorCyclic",
        "nonConformalCyclic",
        "nonConformalMapped",
        "somethingNew",
    ];
    for kind in refused {
        assert_eq!(PatchRole::of_particle_boundary(kind), None, "{kind}");
        for (patch, faces) in [("frontAndBack", 80), ("walls", 20)] {
            let dir = channel_copy(&format!("refused_{kind}_{patch}"));
            retype(&dir, patch, kind);
            let case = FoamCase::open(&dir).unwrap();
            match check_particle_patches(case.mesh()) {
                Err(FoamError::UnsupportedPatch {
                    patch: p,
                    kind: k,
                    faces: n,
                    ..
                }) => {
                    assert_eq!((p.as_str(), k.as_str(), n), (patch, kind, faces));
                }
                other => panic!("{kind} on {patch}: {other:?}"),
            }
        }
    }
    let message = FoamError::UnsupportedPatch {
        patch: "side1".into(),
        kind: "cyclicACMI".into(),
        faces: 3,
        hint: "",
    }
    .to_string();
    assert!(
        message.contains("`side1`")
            && message.contains("`cyclicACMI`")
            && message.contains("not supported as a particle boundary"),
        "{message}"
    );
}

/// A patch without faces cannot be met: a `cyclic` patch of no faces (appended to the
/// channel's boundary file) is let through.
#[test]
fn a_patch_without_faces_is_not_refused() {
    let dir = channel_copy("empty_cyclic");
    let path = dir.join("constant/polyMesh/boundary");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replacen("\n4\n(", "\n5\n(", 1);
    let close = text.rfind(')').unwrap();
    let extra = "    unused\n    {\n        type cyclic;\n        nFaces 0;\n        startFace 174;\n    }\n";
    std::fs::write(&path, format!("{}{extra}{}", &text[..close], &text[close..])).unwrap();
    let case = FoamCase::open(&dir).unwrap();
    assert_eq!(case.mesh().patches().len(), 5);
    check_particle_patches(case.mesh()).unwrap();
}

/// The 2-D channel is extruded along z: its 80 `empty` faces are normal to e₃. With the walls
/// (normal to e₂) also `empty` the faces are normal to two axes (a 1-D case): no one slab axis;
/// nor without `empty` faces.
#[test]
fn a_two_d_mesh_has_its_slab_axis() {
    use pseudorigid::flow::openfoam::slab_axis;
    assert_eq!(slab_axis(FoamCase::open(channel_2d()).unwrap().mesh()), Some(2));
    let dir = channel_copy("walls_empty");
    retype(&dir, "walls", "empty");
    assert_eq!(slab_axis(FoamCase::open(&dir).unwrap().mesh()), None);
    let dir = channel_copy("no_empty");
    retype(&dir, "frontAndBack", "wall");
    assert_eq!(slab_axis(FoamCase::open(&dir).unwrap().mesh()), None);
}
