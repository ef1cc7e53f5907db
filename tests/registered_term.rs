//! A force term registered outside the crate, in one file, is selectable by name and estimated
//! by the validity monitor when a particle leaves it out (issue 40: the monitor kept a closed
//! copy of five terms, so a term added in its own file was neither estimated nor recognised).
//!
//! A test crate of its own, not a module of `suite`: the registration is global to the binary,
//! and the suite pins the crate's registry (`hydro::forces::force_terms_by_name`) and the
//! monitor's flags of its scenes.

use pseudorigid::diagnostics::{Monitor, Thresholds, Validity, omitted_constants};
use pseudorigid::hydro::forces::{
    self, Contribution, FINITE_RE_DRAG, ForceContext, ForceTerm, ForceTerms, Observed, Omission, Registration, Rest,
    Size,
};
use pseudorigid::material::Rigid;
use pseudorigid::prelude::*;
use pseudorigid::registry::Values;
use std::sync::Arc;

/// Oseen's drag, c = 1 + (3/16) Re_p: the first inertial correction of Stokes' law for a
/// sphere (Oseen 1910; Proudman & Pearson 1957), a finite-Re drag correction like
/// Schiller–Naumann's and exclusive with it.
#[derive(Debug)]
struct Oseen;

impl ForceTerm for Oseen {
    fn name(&self) -> &'static str {
        "oseen"
    }

    fn exclusive_group(&self) -> Option<&'static str> {
        Some(FINITE_RE_DRAG)
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        Contribution {
            drag_factor: 1.0 + 3.0 / 16.0 * ctx.reynolds(),
            ..Contribution::default()
        }
    }
}

/// Left out, Oseen's correction changes the drag by (3/16) Re_s.
fn omitted(_: &Rest, at: &Observed) -> f64 {
    3.0 / 16.0 * at.re_slip
}

pseudorigid::hydro::forces::inventory::submit! {
    Registration {
        name: "oseen",
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(Oseen))
        },
        // Between the finite-Re drag (30) and the shear lift (40).
        omitted: Some(Omission { order: 35, carried_by: Some(FINITE_RE_DRAG), size: Size::PerState(omitted) }),
    }
}

/// The diagnostics suite's sphere of d_eq = 2 mm in water (ν = 10⁻⁶ m²/s), in u = γ̇ y e_x with
/// γ̇ = 0.1 s⁻¹, at y = 5 cm and 1 mm/s slower than the fluid: Re_s = 10⁻³ · 2·10⁻³/10⁻⁶ = 2,
/// so Oseen's estimate is 3/8.
fn observed(terms: &[&str]) -> Validity {
    let shape = Ellipsoid::with_volume_diameter([1.0; 3], 2e-3, Mat3::identity()).unwrap();
    let terms = terms
        .iter()
        .map(|t| forces::by_name(t, &Values::new()).unwrap())
        .collect();
    let p = Particle::new(shape, Rigid, Fluid::new(1e-3, 1e3).unwrap(), 1e3)
        .unwrap()
        .with_forces(ForceTerms::new(terms).unwrap())
        .unwrap();
    let flow = LinearFlow::simple_shear(0.1).unwrap();
    let mut monitor = Monitor::in_linear_flow(&p, &flow);
    assert_eq!(
        omitted_constants(&p).size("oseen"),
        Some(0.0),
        "estimated state by state"
    );
    let mut state = State::at_rest(Vec3::new(0.0, 0.05, 0.0));
    state.v = Vec3::new(0.005 - 1e-3, 0.0, 0.0);
    monitor.observe(&state);
    monitor.validity()
}

#[test]
fn a_term_registered_in_its_own_file_is_estimated_when_left_out() {
    assert!(forces::names().contains(&"oseen"));
    let v = observed(&[]);
    let size = v.omitted.size("oseen").unwrap();
    assert!((size / (3.0 / 8.0) - 1.0).abs() < 1e-14, "{size}");
    // Flagged in its order, between the finite-Re drag and the lift (9.1 % of the drag:
    // Mei's fit at Re_s = 2, issue 61; 0.8 % on McLaughlin's J*, before).
    assert_eq!(
        v.flags(&Thresholds::default()),
        [
            "re_shear",
            "re_slip",
            "omits_added_mass",
            "omits_schiller_naumann",
            "omits_oseen",
            "omits_saffman_mei"
        ]
    );
    let names: Vec<&str> = v.omitted.sizes().map(|(name, _)| name).collect();
    assert_eq!(
        names,
        [
            "undisturbed_flow",
            "added_mass",
            "schiller_naumann",
            "oseen",
            "saffman_mei",
            "cunningham"
        ]
    );
    // Recorded by name, and read back in the monitor's order, also from a record's
    // `serde_json::Value`, whose keys are sorted by name.
    let json = serde_json::to_string(&v).unwrap();
    assert!(json.contains("\"oseen\":0.375"), "{json}");
    assert_eq!(serde_json::from_str::<Validity>(&json).unwrap(), v);
    let value = serde_json::to_value(&v).unwrap();
    assert_eq!(serde_json::from_value::<Validity>(value).unwrap(), v);
}

#[test]
fn a_term_carried_or_covered_by_its_group_is_not_estimated() {
    // Carried: no estimate of its own, and Schiller–Naumann's is not taken either (Oseen is a
    // finite-Re drag correction).
    let v = observed(&["oseen"]);
    assert_eq!(v.omitted.size("oseen"), Some(0.0));
    assert_eq!(v.omitted.size("schiller_naumann"), Some(0.0));
    // Covered by another term of its group.
    let v = observed(&["schiller_naumann"]);
    assert_eq!(v.omitted.size("oseen"), Some(0.0));
    assert_eq!(
        v.flags(&Thresholds::default()),
        ["re_shear", "re_slip", "omits_added_mass", "omits_saffman_mei"]
    );
    // And exclusive with it, as the group says.
    let both = ["schiller_naumann", "oseen"].map(|t| forces::by_name(t, &Values::new()).unwrap());
    assert!(ForceTerms::new(both.to_vec()).is_err());
}

/// Selectable from a scene file, its parameters refused at their key like every registry's.
#[cfg(feature = "cli")]
#[test]
fn a_term_registered_in_its_own_file_is_selectable_from_a_scene() {
    use pseudorigid::scene::SceneError;
    use pseudorigid::scene::error::Source;
    use pseudorigid::scene::parse;
    let text = |forces: &str| {
        format!(
            "[flow]\ntype = \"quiescent\"\n[fluid]\nviscosity = 1e-3\ndensity = 1e3\n[particles]\ndensity = 2e3\n\
             forces = {forces}\n[[particles.list]]\nsemi_axes = [1e-3, 1e-3, 1e-3]\nposition = [0.0, 0.0, 0.0]\n\
             material = {{ law = \"rigid\" }}\n[integrator]\ntype = \"stokesian\"\ntol = 1e-6\ndt = 1e-4\n\
             [end]\nt_end = 1e-2\n"
        )
    };
    let parse = |text: &str| {
        parse(
            &Source {
                file: "oseen.toml",
                text,
            },
            std::path::Path::new("."),
        )
    };
    assert!(parse(&text("[\"oseen\"]")).is_ok());
    match parse(&text("[{ term = \"oseen\", c = 0.1875 }]")) {
        Err(SceneError::Invalid { key, message, .. }) => {
            assert_eq!(key, "particles.forces[0].c", "{message}");
            assert!(message.contains("`oseen` does not take `c`"), "{message}");
        }
        other => panic!("expected a scene error, got {:?}", other.map(|s| s.count())),
    }
}
