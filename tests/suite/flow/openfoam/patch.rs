//! Patch types as OpenFOAM writes them: a 2-D case's `empty` patches read (the fixture
//! `tests/data/channel-2d`, as simpleFoam wrote it).

use pseudorigid::flow::openfoam::{FoamCase, FoamError};
use std::path::{Path, PathBuf};

fn channel_2d() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/channel-2d")
}

/// A copy of the 2-D channel in a scratch directory, to be altered.
fn channel_copy(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("flow_openfoam_patch")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    for sub in ["constant/polyMesh", "117"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
        for e in std::fs::read_dir(channel_2d().join(sub)).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), dir.join(sub).join(e.file_name())).unwrap();
        }
    }
    dir
}

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
