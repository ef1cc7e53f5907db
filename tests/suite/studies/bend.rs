//! The 90° bend (issue 25, deliverable 3) at reduced size, on the coarse field shipped in
//! `tests/data/bend-coarse` (`cases/bend/Allrun DIR 6 6 6`, then `cases/bend/Allship DIR`).
#![cfg(all(feature = "cli", feature = "plot"))]

use pseudorigid::population::RunOptions;
use pseudorigid::studies::bend::{BendCase, BendError, SEED, Settings, deposition_table};
use std::path::{Path, PathBuf};

fn coarse() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bend-coarse")
}

/// The case's summary: Re from OpenFOAM's own inlet flow rate, the residence time from the
/// tubes' length, and d from the Stokes number (Stk = ρ_p d² U/(18 μ a) inverted, checked by
/// putting d back: exact to rounding).
#[test]
fn summary_reynolds_and_diameter() {
    let case = BendCase::open(coarse()).unwrap();
    assert_eq!(case.cells, 10_080);
    // The Poiseuille profile sampled at the face centres of a 24-gon: Re within 1 % of 1000.
    assert!((case.reynolds() / 1000.0 - 1.0).abs() < 0.01, "Re {}", case.reynolds());
    let d = case.diameter_for_stokes(0.3).unwrap();
    let mu = 1.2 * case.nu;
    let stk = 1000.0 * d * d * case.mean_velocity / (18.0 * mu * case.radius);
    assert!((stk / 0.3 - 1.0).abs() < 1e-12, "{stk}");
    assert!(case.diameter_for_stokes(0.0).is_err());
    assert!(
        case.scene_text(
            0.3,
            10,
            1,
            Settings {
                tol: -1.0,
                ..Settings::default()
            }
        )
        .is_err()
    );
}

/// A folder without `bend.summary`, and one with a malformed value, are typed errors.
#[test]
fn bad_summary_is_an_error() {
    let dir = std::env::temp_dir().join(format!("pseudorigid-bend-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    assert!(matches!(BendCase::open(&dir), Err(BendError::Summary { .. })));
    std::fs::write(
        dir.join("bend.summary"),
        "radius=2.5e-3\nnu=-1\nmean_velocity=3\ncells=10\n",
    )
    .unwrap();
    let err = BendCase::open(&dir).unwrap_err();
    assert!(err.to_string().contains("nu=-1"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Reduced dataset: 200 spheres at Stk 0.2, 0.3 and 1 on the coarse field, rounded to what
/// 200 particles resolve (counts are exact: the runs are bitwise deterministic), and the
/// subsample against the full-N run of the same field and the same particle streams
/// (`paper-figures/bend/coarse/deposition.csv`, N = 2000, the first 200 of which are these):
/// the subsample's DE differs from the whole's by a binomial with sd √(p(1 − p)(1/n − 1/N));
/// 4 sd is a false alarm below 10⁻⁴ per row.
///
/// Regression guard, not a check: both the snapshot and the dataset are this code's output,
/// so they show that the reduced run still agrees with the committed dataset, not that
/// either is right. The bend's checks against outside references are the plug-flow closed
/// form (`studies::bend_plug`) and OpenFOAM's own tracker on the same spheres and field,
/// paired (`paper-figures/bend/NOTES.md`, not run in the suite: it needs OpenFOAM).
#[test]
fn reduced_bend_dataset_snapshot() {
    let case = BendCase::open(coarse()).unwrap();
    let n = 200;
    let rows: Vec<_> = [0.2, 0.3, 1.0]
        .iter()
        .map(|&stk| {
            case.run(stk, n, SEED, Settings::default(), RunOptions::default().quiet())
                .unwrap()
        })
        .collect();
    for r in &rows {
        assert_eq!(r.failed, 0, "Stk {}: failed particles", r.stokes);
        assert_eq!(r.bend + r.tubes + r.escaped + r.suspended, n);
    }
    // DE rises with Stk (the centrifugal drift τu²/R_o grows with τ).
    assert!(rows.windows(2).all(|w| w[0].de() <= w[1].de()), "{rows:?}");
    insta::assert_snapshot!(deposition_table(&rows).unwrap().to_text());

    let table =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("paper-figures/bend/coarse/deposition.csv"))
            .unwrap();
    for r in &rows {
        let line = table
            .lines()
            .find(|l| l.split(',').next().and_then(|s| s.parse::<f64>().ok()) == Some(r.stokes))
            .expect("dataset row");
        let cells: Vec<&str> = line.split(',').collect();
        let (n_all, p): (f64, f64) = (cells[1].parse().unwrap(), cells[3].parse().unwrap());
        let sd = (p * (1.0 - p) * (1.0 / n as f64 - 1.0 / n_all)).sqrt();
        assert!(
            (r.de() - p).abs() <= 4.0 * sd + 1e-12,
            "Stk {}: DE {} vs dataset {p} (sd {sd})",
            r.stokes,
            r.de()
        );
    }
}

/// The paired comparison by hand: b = 3 (ours only), c = 1 (peer only), n = 10: difference
/// (b − c)/n = 0.2, McNemar's standard error √(b + c − (b − c)²/n)/n = √3.6/10, χ² = 4/4 = 1;
/// a peer file with another header or a bad index is a typed error.
#[test]
fn peer_pairing_by_hand() {
    use pseudorigid::population::peer::{Pairing, PeerError, read_peer_fates};
    let mut p = Pairing::default();
    for (ours, peer) in [(true, false); 3]
        .into_iter()
        .chain([(false, true)])
        .chain([(true, true); 2])
        .chain([(false, false); 4])
    {
        p.add(ours, peer);
    }
    assert_eq!((p.both, p.only_ours, p.only_peer, p.neither, p.n()), (2, 3, 1, 4, 10));
    let (d, se) = p.difference();
    assert!(
        (d - 0.2).abs() < 1e-15 && (se - 3.6f64.sqrt() / 10.0).abs() < 1e-15,
        "{d} {se}"
    );
    assert!((p.mcnemar_chi2() - 1.0).abs() < 1e-15);
    let dir = std::env::temp_dir().join(format!("pseudorigid-peer-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("fates.csv");
    std::fs::write(&file, "index,fate,patch,t,x,y,z\n3,deposited,wall_bend,0.01,1,2,3\n").unwrap();
    let fates = read_peer_fates(&file).unwrap();
    assert_eq!(fates[&3].patch, "wall_bend");
    std::fs::write(&file, "i,fate\n").unwrap();
    assert!(matches!(read_peer_fates(&file), Err(PeerError::Format { .. })));
    std::fs::write(&file, "index,fate,patch,t,x,y,z\nx,deposited,w,0,1,2,3\n").unwrap();
    assert!(matches!(read_peer_fates(&file), Err(PeerError::Format { .. })));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The race's settings: an integrator chosen by name (aliases to the registered name, unknown
/// names a typed error listing the known ones; one that takes no `tol` refused by the scene)
/// and soft spheres (neo-Hookean, λ_s = 10³ μ_s; a shear modulus ≤ 0 refused).
#[test]
fn race_settings_in_the_scene() {
    use pseudorigid::studies::bend::{BULK_RATIO, integrator_name};
    assert_eq!(integrator_name("stokesian").unwrap(), "radau_iia");
    assert_eq!(integrator_name("rosenbrock_w23").unwrap(), "rosenbrock_w23");
    assert!(integrator_name("bogus").unwrap_err().to_string().contains("radau_iia"));
    let case = BendCase::open(coarse()).unwrap();
    let soft = Settings {
        shear_modulus: Some(1.0),
        integrator: "rosenbrock_w23",
        ..Settings::default()
    };
    let text = case.scene_text(0.3, 4, SEED, soft).unwrap();
    assert!(
        text.contains(&format!("law = \"neo_hooke\", mu = 1e0, lambda = {:e}", BULK_RATIO)),
        "{text}"
    );
    assert!(text.contains("type = \"rosenbrock_w23\""), "{text}");
    assert!(case.scene(0.3, 4, SEED, soft).is_ok());
    let bad = Settings {
        shear_modulus: Some(-1.0),
        ..Settings::default()
    };
    assert!(case.scene_text(0.3, 4, SEED, bad).is_err());
    let fixed_step = Settings {
        integrator: integrator_name("imex").unwrap(),
        ..Settings::default()
    };
    assert!(matches!(case.scene(0.3, 4, SEED, fixed_step), Err(BendError::Cli(_))));
}

/// The race's spheres: OpenFOAM's particles are the runner's (same points and velocities, the
/// diameter of the Stokes number); rigid spheres on 1 and 2 threads give the same records
/// (the runner is deterministic for any thread count), and soft ones run to a fate.
#[test]
fn race_spheres_on_the_coarse_bend() {
    use pseudorigid::studies::bend::on_bend_wall;
    let case = BendCase::open(coarse()).unwrap();
    let n = 8;
    let particles = case.peer_particles(0.3, n, SEED).unwrap();
    let specs = case.particle_specs(0.3, n, SEED).unwrap();
    assert_eq!(particles.len(), n as usize);
    for (p, s) in particles.iter().zip(&specs) {
        assert_eq!((p.position, p.velocity), (s.position, s.velocity));
        assert_eq!(p.diameter, case.diameter_for_stokes(0.3).unwrap());
    }
    let run = |threads: usize, settings: Settings| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| case.run_output(0.3, n, SEED, settings, RunOptions::default().quiet()))
            .unwrap()
    };
    let one = run(1, Settings::default());
    let two = run(2, Settings::default());
    assert_eq!(one.records, two.records);
    let soft = run(
        1,
        Settings {
            shear_modulus: Some(1.0),
            ..Settings::default()
        },
    );
    assert!(
        soft.records
            .iter()
            .all(|r| !matches!(r.fate, pseudorigid::population::Fate::Failed { .. }))
    );
    // Deposition on the bend's wall by name, as the DE counts it.
    let bend = one.records.iter().filter(|r| on_bend_wall(r, &one.patches)).count();
    assert_eq!(
        bend as u64,
        case.run(0.3, n, SEED, Settings::default(), RunOptions::default().quiet())
            .unwrap()
            .bend
    );
}
