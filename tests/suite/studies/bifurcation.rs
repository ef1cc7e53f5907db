//! The airway bifurcation of paper §6.4 (src/studies/bifurcation).

use pseudorigid::flow::FlowField;
use pseudorigid::studies::bifurcation::setup::{self, Airway};
use pseudorigid::tensor::Vec3;
use std::sync::OnceLock;

fn airway() -> &'static Airway {
    static AIRWAY: OnceLock<Airway> = OnceLock::new();
    AIRWAY.get_or_init(|| Airway::open(Airway::shipped_dir()).expect("shipped bifurcation field"))
}

/// The paper's pairs Stk 0.1 ↔ d_eq = 8.06 µm, 0.4 ↔ 16.12 µm, 0.5 ↔ 18.03 µm hold with
/// ρ_p/ρ_f = 1994: the diameters are printed to ±0.005 µm, so Stk (∝ d²) is fixed to a relative
/// 2·0.005/d_eq (1.2e-3 at 8.06 µm); the inverse is exact to round-off (1e-14).
#[test]
fn stokes_number_from_the_paper_pairs() {
    for (stk, d_um) in [(0.1, 8.06), (0.4, 16.12), (0.5, 18.03)] {
        let got = setup::stokes_number(d_um * 1e-6).unwrap();
        let allowed = 2.0 * 0.005 / d_um;
        assert!(
            (got / stk - 1.0).abs() <= allowed,
            "d_eq {d_um} µm: Stk {got}, want {stk} ± {allowed}"
        );
        let d = setup::d_eq_for_stokes(stk).unwrap();
        assert!((setup::stokes_number(d).unwrap() / stk - 1.0).abs() < 1e-14);
    }
    assert!(setup::stokes_number(0.0).is_err());
    assert!(setup::d_eq_for_stokes(f64::NAN).is_err());
    assert!((setup::inlet_velocity() - 1.2425).abs() < 1e-12);
}

/// The shipped field carries the case's patches with their roles, and conserves the inlet flow
/// rate U πR² through a cross-section of the parent (x₁ = 10 mm) and of each daughter (the plane
/// x₁ = 36 mm, one half each). The flux of the cellwise field is integrated by the midpoint rule
/// on a 0.05 mm grid over the points the mesh contains; the error budget is the reconstruction's O(h²) velocity error
/// ((0.3/3)² ≈ 1 % of the peak near the wall, less on average), the faceted wall (area deficit
/// ≈ (h/R)²/6 ≈ 0.2 %) and the grid's boundary cells (a 0.05 mm band where u ≈ 0): 3 %.
/// The two daughters split the flow equally by symmetry, to the same 3 %.
#[test]
fn shipped_field_conserves_the_flow_rate() {
    let a = airway();
    let names: Vec<String> = a
        .flow()
        .cellwise()
        .mesh()
        .patches()
        .iter()
        .map(|p| p.name.clone())
        .collect();
    for want in ["inlet", "outlet1", "outlet2", "wall"] {
        assert!(names.iter().any(|n| n == want), "patch {want} missing: {names:?}");
    }
    let q_in = setup::inlet_velocity() * std::f64::consts::PI * setup::RADIUS * setup::RADIUS;
    let h = 5e-5;
    let flux = |x1: f64, y_from: f64, y_to: f64| {
        let mut q = 0.0;
        let ny = ((y_to - y_from) / h).round() as i64;
        let nz = (2.0 * setup::RADIUS / h).round() as i64 + 2;
        for j in 0..ny {
            for k in 0..nz {
                let x = Vec3::new(
                    x1,
                    y_from + (j as f64 + 0.5) * h,
                    -setup::RADIUS - h + (k as f64 + 0.5) * h,
                );
                if let Ok(s) = a.flow().cellwise().sample(&x, 0.0) {
                    q += s.u[0] * h * h;
                }
            }
        }
        q
    };
    let parent = flux(0.01, -setup::RADIUS - h, setup::RADIUS + h);
    assert!((parent / q_in - 1.0).abs() < 0.03, "parent: {parent:e} vs {q_in:e}");
    let upper = flux(0.036, 0.0, 0.0135);
    let lower = flux(0.036, -0.0135, 0.0);
    for (name, q) in [("outlet1 side", upper), ("outlet2 side", lower)] {
        assert!(
            (q / (0.5 * q_in) - 1.0).abs() < 0.03,
            "{name}: {q:e} vs {:e}",
            0.5 * q_in
        );
    }
}

/// The blended field reproduces a linear field u = a + Bx (and ∇u = B) on a snapped mesh with
/// prisms and split-hex polyhedra: every cell fit is exact for linear fields and the weights
/// sum to one, so only round-off remains. The fits solve small least-squares systems whose
/// condition on snapped cells stays below ~10⁴; with |u| ≈ 1 that bounds the error by
/// 10⁴ · 2.2e-16 · (terms ≈ 10) ≈ 2e-11, and 1e-9 leaves room for summation order.
#[test]
fn blended_field_is_exact_for_linear_fields() {
    use pseudorigid::flow::openfoam::{BlendedFlow, FoamFlow, PolyMesh, VolField};
    use pseudorigid::tensor::Mat3;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reference-data/snappy-sphere/n10");
    let mesh = PolyMesh::read(&dir).unwrap();
    let a = Vec3::new(0.3, -0.2, 0.1);
    let b = Mat3::new(0.5, -1.0, 0.25, 0.7, 0.1, -0.3, -0.2, 0.4, -0.6);
    let lin = |x: &Vec3| a + b * x;
    let internal = mesh
        .cell_centres()
        .iter()
        .flat_map(|c| lin(c).iter().copied().collect::<Vec<_>>())
        .collect();
    let boundary = (mesh.n_internal_faces()..mesh.n_faces())
        .flat_map(|f| lin(&mesh.face_centres()[f]).iter().copied().collect::<Vec<_>>())
        .collect();
    // No patch prescribes the value: a linear field that does not vanish on the sphere is no
    // no-slip flow, and the blend's wall terms are exact only for such flows (they are tested
    // in tests/flow_openfoam.rs).
    let field = VolField {
        comps: 3,
        internal,
        boundary,
        fixed: vec![false; mesh.patches().len()],
    };
    let flow = BlendedFlow::new(FoamFlow::new(mesh.clone(), vec![(0.0, field)]).unwrap()).unwrap();
    let mut checked = 0;
    for c in (0..mesh.n_cells()).step_by(7) {
        // Points between a cell centre and one of its face centres lie inside that cell.
        let face = mesh.cell_faces(c)[0] as usize;
        let x = mesh.cell_centres()[c] * 0.7 + mesh.face_centres()[face] * 0.3;
        let s = flow.sample(&x, 0.0).unwrap();
        assert!((s.u - lin(&x)).amax() < 1e-9, "cell {c}: u {:?} vs {:?}", s.u, lin(&x));
        assert!((s.grad_u - b).amax() < 1e-9, "cell {c}: grad {:?}", s.grad_u);
        checked += 1;
    }
    assert!(checked > 50);
}

/// The blended field is continuous: along a line through the parent and across the carina,
/// sampled every δ = 1 µm (hundreds of cell faces crossed), no step changes u by more than
/// δ times 10 max|∇u| — the blend's derivative is the cells' gradients plus the weights'
/// derivatives (≤ 5/r for Wendland's C² weight) times the differences between neighbouring
/// fits, O(h²|∇²u|), which is of the order of |∇u| h ≤ |∇u| r. The cellwise field jumps by
/// O(h²|∇²u|) at faces, independent of δ, and fails the same bound.
#[test]
fn blended_field_is_continuous() {
    let a = airway();
    let delta = 1e-6;
    let (mut worst_blend, mut worst_cells, mut grad_max): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let path = |k: usize| Vec3::new(0.004 + k as f64 * delta, 3e-4, 2e-4);
    let mut prev: Option<(Vec3, Vec3)> = None;
    for k in 0..26_000 {
        let x = path(k);
        let (Ok(s), Ok(c)) = (a.flow().sample(&x, 0.0), a.flow().cellwise().sample(&x, 0.0)) else {
            prev = None;
            continue;
        };
        grad_max = grad_max.max(s.grad_u.norm());
        if let Some((u_blend, u_cells)) = prev {
            worst_blend = worst_blend.max((s.u - u_blend).norm());
            worst_cells = worst_cells.max((c.u - u_cells).norm());
        }
        prev = Some((s.u, c.u));
    }
    let bound = 10.0 * grad_max * delta;
    assert!(grad_max > 0.0);
    assert!(worst_blend <= bound, "blended jump {worst_blend:e} > {bound:e}");
    assert!(
        worst_cells > bound,
        "cellwise jump {worst_cells:e} (expected jumps at faces)"
    );
}

/// Injection (paper §6.4): points uniform by area on the 5.5 mm disc at x₁ = 0.2 mm, velocity
/// the local fluid velocity, orientation a rotation, and particle k the same whatever else was
/// drawn. Uniform by area means ρ²/R² is uniform on [0, 1]: its mean over 2000 draws is ½ with
/// standard error 1/√(12·2000) = 0.0065; 4 standard errors (0.026) fail by chance once in
/// 1.6·10⁴ seeds. The same for the polar angle's cosine (mean 0, standard error
/// 1/√(2·2000) = 0.016, so 0.064).
#[test]
fn injection_is_uniform_on_the_disc_with_the_fluid_velocity() {
    use pseudorigid::population::{Injector, particle_rng};
    use pseudorigid::studies::bifurcation::{Injection, Kind, Material};
    use pseudorigid::studies::cavity::Shape;
    let a = airway();
    let kind = Kind {
        shape: Shape::Prolate(5.0),
        material: Material::ShearModulus(0.5),
        stokes: 0.1,
    };
    let inj = Injection::new(a, kind).unwrap();
    let r = 0.5 * setup::INJECTION_DIAMETER;
    let (mut rho2, mut cos) = (0.0, 0.0);
    let n = 2000;
    for k in 0..n {
        let spec = inj.draw(k, &mut particle_rng(7, k)).unwrap();
        let again = inj.draw(k, &mut particle_rng(7, k)).unwrap();
        assert_eq!(spec, again);
        let p = spec.position;
        assert_eq!(p[0], setup::INJECTION_X);
        let rr = (p[1] * p[1] + p[2] * p[2]) / (r * r);
        assert!(rr <= 1.0);
        rho2 += rr;
        cos += p[1] / (p[1] * p[1] + p[2] * p[2]).sqrt();
        assert_eq!(spec.velocity, a.flow().sample(&p, 0.0).unwrap().u);
        let axes = spec.shape.axes();
        assert!((axes.transpose() * axes - pseudorigid::tensor::Mat3::identity()).amax() < 1e-12);
        let semi = spec.shape.semi_axes();
        let d_eq = 2.0 * semi.product().cbrt();
        assert!((d_eq / setup::d_eq_for_stokes(0.1).unwrap() - 1.0).abs() < 1e-12);
    }
    assert!(
        (rho2 / n as f64 - 0.5).abs() < 0.026,
        "mean rho²/R² {}",
        rho2 / n as f64
    );
    assert!((cos / n as f64).abs() < 0.064, "mean cos {}", cos / n as f64);
}

/// The first 200 soft spheres (μ_s = 0.5 Pa) at Stk = 0.4 of the Fig. 19 dataset: their fates
/// are a snapshot (a change in the model, integrator or field shows here), and their DE agrees
/// with the dataset's DE over N particles (`paper-figures/fig19/de.csv`, same seed). These 200
/// are the dataset's first 200, so DE₂₀₀ − DE_N has standard deviation
/// √(p(1 − p)(1/200 − 1/N)) (a subsample against its whole); 4 of them fail by chance with
/// probability 6e-5. No particle may fail. The deposits' left stretch satisfies V² = F̄F̄ᵀ (a
/// symmetric square root: round-off of the 3×3 eigen-decomposition, 1e-10 of |F̄|²).
/// `Injection::particle_spec` gives each record's particle exactly (the same draw).
///
/// Regression guard, not a check: the snapshot and the Fig. 19 dataset are both this code's
/// output, so their agreement shows that the reduced run still reproduces the dataset, not
/// that either is right.
#[test]
fn soft_spheres_at_stokes_0_4_snapshot() {
    use pseudorigid::population::{Injector, RunOptions};
    use pseudorigid::studies::bifurcation::{Efficiency, Injection, Kind, Material, StudyRun, deposition, figures};
    use pseudorigid::studies::cavity::Shape;
    let a = airway();
    let kind = Kind {
        shape: Shape::Prolate(1.0),
        material: Material::ShearModulus(0.5),
        stokes: 0.4,
    };
    let n = 200;
    let out = StudyRun::new(a, kind, n).run(&RunOptions::default().quiet()).unwrap();
    let row = Efficiency::of(kind, &out);
    assert_eq!(row.counts.failed, 0);
    insta::assert_snapshot!(format!(
        "deposited {} escaped {} suspended {} failed {}",
        row.counts.deposited, row.counts.escaped, row.counts.suspended, row.counts.failed
    ));
    let table =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("paper-figures/fig19/de.csv"))
            .unwrap();
    let line = table
        .lines()
        .find(|l| {
            l.starts_with("prolate_1,")
                && l.split(',').nth(2) == Some("0.4")
                && l.contains(&format!("{:.4e}", Material::ShearModulus(0.5).capillary_number()))
        })
        .expect("dataset row");
    let cells: Vec<&str> = line.split(',').collect();
    let (n_all, p): (f64, f64) = (cells[3].parse().unwrap(), cells[7].parse().unwrap());
    let sd = (p * (1.0 - p) * (1.0 / n as f64 - 1.0 / n_all)).sqrt();
    assert!(
        (row.de() - p).abs() <= 4.0 * sd + 1e-12,
        "DE {} vs dataset {p} (sd {sd})",
        row.de()
    );
    let inj = Injection::new(a, kind).unwrap();
    // `particle_spec` (what examples/openfoam_peer hands to OpenFOAM) is what the runner drew.
    for r in &out.records {
        assert_eq!(
            Some(inj.particle_spec(figures::SEED, r.index).unwrap()),
            r.spec,
            "particle {}",
            r.index
        );
    }
    for d in deposition::deposits(a, kind, &out).unwrap() {
        let r = &out.records[d.index as usize];
        let f_bar = inj
            .particle(r.spec.as_ref().unwrap())
            .unwrap()
            .total_distortion(&r.end.unwrap().f);
        let b = f_bar * f_bar.transpose();
        assert!((d.v * d.v - b).amax() <= 1e-10 * b.amax(), "particle {}", d.index);
    }
}

/// Histogram bins and the mean position of deposits at known places.
#[test]
fn histogram_and_mean_of_known_deposits() {
    use pseudorigid::studies::bifurcation::deposition::{Deposit, histogram, mean_position};
    use pseudorigid::tensor::Mat3;
    let at = |x1: f64| Deposit {
        index: 0,
        x: Vec3::new(x1 * setup::LENGTH, 0.0, 0.0),
        patch: 0,
        v: Mat3::identity(),
        r: Vec3::repeat(1.0),
    };
    let deps = [at(0.01), at(0.77), at(0.771), at(0.999), at(1.2), at(-0.1)];
    let h = histogram(&deps, 10);
    assert_eq!(h, vec![2, 0, 0, 0, 0, 0, 0, 2, 0, 2]);
    let (mean, se) = mean_position(&deps[1..3]).unwrap();
    assert!((mean - 0.7705).abs() < 1e-12);
    // Sample standard deviation of {0.77, 0.771} is 0.001/√2; over √2: 0.0005.
    assert!((se - 0.0005).abs() < 1e-12);
    assert!(mean_position(&deps[..1]).is_none());
}

/// The deposition maps' ParaView file holds every deposit of every run, in run order, with
/// the deposit's own V, semi-axes and patch (copied, so exactly equal), and `kind` numbering
/// the runs.
#[test]
fn deposition_map_vtp_holds_every_deposit() {
    use pseudorigid::studies::bifurcation::deposition::Deposit;
    use pseudorigid::studies::bifurcation::figures::deposits_vtp;
    use pseudorigid::studies::bifurcation::{Kind, Material};
    use pseudorigid::studies::cavity::Shape;
    use pseudorigid::tensor::Mat3;
    let deposit = |index: u64, r: [f64; 3], patch: usize| Deposit {
        index,
        x: Vec3::new(index as f64 * 1e-3, 0.0, 0.0),
        patch,
        v: Mat3::from_diagonal(&Vec3::from(r)),
        r: Vec3::from(r),
    };
    let kind = |stokes| Kind {
        shape: Shape::Prolate(2.0),
        material: Material::Rigid,
        stokes,
    };
    let runs = vec![
        (kind(0.1), 10, vec![deposit(3, [3e-6, 2e-6, 1e-6], 4)]),
        (
            kind(0.4),
            10,
            vec![deposit(1, [4e-6, 2e-6, 2e-6], 5), deposit(7, [5e-6, 1e-6, 1e-6], 4)],
        ),
    ];
    let xml = deposits_vtp(&runs).unwrap().to_xml();
    assert!(xml.contains("NumberOfPoints=\"3\""), "{xml}");
    for array in ["id", "kind", "patch", "V", "r1", "r2", "r3"] {
        assert!(xml.contains(&format!("Name=\"{array}\"")), "array {array} missing");
    }
    assert!(xml.contains("Tensors=\"V\""));
}

/// The effective-Stokes table: a sphere keeps its Stk, a λ = 20 prolate's is halved (its
/// orientation-averaged response time is 0.5012 of its volume-equivalent sphere's, checked
/// against quadrature in `tests/hydro.rs`), and the correlation is read at both.
#[test]
fn effective_stokes_scales_stk_by_the_response_time_ratio() {
    use pseudorigid::population::FateCounts;
    use pseudorigid::studies::bifurcation::{Efficiency, Kind, Material, study, zhang_reference};
    use pseudorigid::studies::particles::Shape;
    let row = |shape, stokes| Efficiency {
        kind: Kind {
            shape,
            material: Material::Rigid,
            stokes,
        },
        counts: FateCounts {
            deposited: 10,
            escaped: 90,
            suspended: 0,
            failed: 0,
        },
    };
    let text = study::effective_stokes_table(&[row(Shape::Prolate(1.0), 0.1), row(Shape::Prolate(20.0), 0.2)])
        .unwrap()
        .to_text();
    let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        lines[0],
        [
            "shape",
            "stk",
            "response_time_ratio",
            "stk_effective",
            "de",
            "de_stderr",
            "zhang_at_stk",
            "zhang_at_stk_effective"
        ]
    );
    assert_eq!(lines[1][2..4], ["1.00000", "0.10000"]);
    assert_eq!(lines[2][2..4], ["0.50120", "0.10024"]);
    let zhang = |stk: f64| format!("{:.5}", zhang_reference(stk).unwrap());
    assert_eq!(lines[2][6], zhang(0.2));
    assert_eq!(lines[2][7], zhang(0.2 * 0.501_199_955_572_886_7));
    // DE = 10/100 with its binomial error √(0.1·0.9/100) = 0.03.
    assert_eq!(lines[1][4..6], ["0.10000", "0.03000"]);
}

/// The error-norm study (`examples/error_norm.rs`, `paper-figures/work-precision/error_norm.csv`)
/// at N = 40 of each of two of its kinds, without the CPU column: steps, rejections, deposits
/// and the fates that differ from Radau IIA at rtol 10⁻⁵. The reference is independent of the
/// norm (10³× tighter), and every setting must keep the fates within the studies' argued
/// tolerance of it: at most 2 of 40 change (1 in 10² for soft prolates, `study::RTOL`, with
/// room for one more at this N).
///
/// The snapshot is a regression guard; the bound on changed fates against the tight run is a
/// convergence check of the step control, not of the physics.
#[test]
fn error_norm_study_snapshot() {
    use pseudorigid::studies::bifurcation::error_norm::{SETTINGS, compare, table};
    use pseudorigid::studies::bifurcation::{Kind, Material, figures};
    use pseudorigid::studies::cavity::Shape;
    let mut rows = Vec::new();
    for (shape, material, stokes) in [
        (Shape::Prolate(20.0), Material::Rigid, 0.2),
        (Shape::Sphere, Material::ShearModulus(1.0), 0.1),
    ] {
        rows.extend(
            compare(
                airway(),
                Kind {
                    shape,
                    material,
                    stokes,
                },
                &SETTINGS,
                40,
                figures::SEED,
            )
            .unwrap(),
        );
    }
    for r in &rows {
        assert!(r.fates_changed <= 2, "{r:?}");
    }
    insta::assert_snapshot!(table(&rows, false).unwrap().to_text());
}

/// Two soft prolates (λ₁ = 5, μ_s = 0.5 Pa, Stk 0.1) of Fig. 19's run at N = 10⁵ slid along the
/// wall 20 µm from it and then failed outside the mesh: at a kink of the wall the support
/// point projected past every nearby face and into a face of the opposite wall, so the gap
/// jumped from 2.4·10⁻⁵ to 5.8·10⁻³ m and the next steps crossed the wall unseen
/// (`contact::mesh`, "Faces the support point misses"). Run alone with the studies' integrator,
/// each now ends deposited or escaped.
#[test]
fn particles_sliding_past_a_wall_kink_stay_inside() {
    use pseudorigid::population::{RunOptions, Shard};
    use pseudorigid::studies::bifurcation::StudyRun;
    use pseudorigid::studies::bifurcation::{Kind, Material};
    use pseudorigid::studies::particles::Shape;
    let kind = Kind {
        shape: Shape::Prolate(5.0),
        material: Material::ShearModulus(0.5),
        stokes: 0.1,
    };
    for index in [8553, 85238] {
        let out = StudyRun::new(airway(), kind, 100_000)
            .shard(Shard::new(index, 100_000).unwrap())
            .run(&RunOptions::default().quiet())
            .unwrap();
        crate::common::assert_single_run_ends(&out, &format!("particle {index}"));
    }
}

/// The studies' integrator puts an elastic particle on the slow manifold only where its shape
/// ratio δ̄ = γ̇/k is at most `MANIFOLD_SHARE` of δ_max = √rtol: every soft kind of the datasets
/// (μ_s = 1 and 0.5 Pa; spheres and λ = 2, 5 prolates; Figs 19–23, the breathing and release
/// studies) keeps the full shape model, so the switch moved no dataset, and 5 Pa spheres
/// (δ̄/δ_max = 0.15, measured in `integrator::choice::MANIFOLD_SHARE`) take the manifold.
#[test]
fn datasets_soft_kinds_keep_the_full_model_and_stiff_ones_take_the_manifold() {
    use pseudorigid::integrator::choice::Chosen;
    use pseudorigid::studies::bifurcation::figures::softness_kinds;
    use pseudorigid::studies::bifurcation::study::integrator;
    use pseudorigid::studies::bifurcation::{Kind, Material};
    use pseudorigid::studies::particles::Shape;
    for kind in softness_kinds(&[1.0, 2.0, 5.0], &[1e5, 1.0, 0.5], &[0.1, 0.4]) {
        let choice = integrator(airway(), kind).unwrap();
        assert!(
            matches!(choice.integrator, Chosen::Full(_)),
            "{kind:?}: {}",
            choice.reason
        );
    }
    let stiff = Kind {
        shape: Shape::Sphere,
        material: Material::ShearModulus(5.0),
        stokes: 0.1,
    };
    let choice = integrator(airway(), stiff).unwrap();
    assert!(
        matches!(choice.integrator, Chosen::SlowManifold(_)),
        "{}",
        choice.reason
    );
}

/// `Allrun 0.12e-3` labels its case `h=0.12mm`: 0.12e-3 · 10³ is 0.12000000000000001 in f64,
/// which the label printed before it rounded to the micrometre.
#[test]
fn case_labels_print_the_cell_size_as_allrun_was_given_it() {
    use pseudorigid::studies::bifurcation::figures::{case_label, millimetres};
    assert_eq!(format!("{}", 0.12e-3 * 1e3), "0.12000000000000001");
    for (given, printed) in [(0.12e-3, "0.12"), (0.15e-3, "0.15"), (0.75e-3, "0.75"), (0.3e-3, "0.3")] {
        assert_eq!(format!("{}", millimetres(given)), printed);
    }
    let dir = std::env::temp_dir().join(format!("pseudorigid-label-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("log.summary"), "cell_size=0.12e-3\nlayers=2\ncells=1114397\n").unwrap();
    let label = case_label(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(label.unwrap(), "h=0.12mm layers=2");
}
