//! Bad scene files: two valid base scenes with every key mutated in turn (a bad number, a
//! wrong type, the key removed, an unknown key added), and a property test breaking two keys
//! at once. Validation must never panic,
//! and every error must name the offending key (in its `key` field or its message) and point
//! at a line of the file.

use proptest::prelude::*;
use pseudorigid::scene::SceneError;
use pseudorigid::scene::error::Source;
use pseudorigid::scene::parse;
use std::path::Path;

/// A pipe with a listed particle: Poiseuille flow, gravity, pipe wall, orientation, fluid
/// velocity, Neo-Hooke, the paper's IMEX scheme.
const LISTED: &str = r#"seed = 3
[flow]
type = "poiseuille"
radius = 10.0
mean_velocity = 2.0
[fluid]
viscosity = 1.0
density = 1.0
gravity = [0.0, -1.0, 0.0]
[boundary]
type = "pipe"
radius = 10.0
[particles]
density = 2.0
drag = "brenner"
[[particles.list]]
semi_axes = [1.0, 0.5, 0.5]
position = [0.0, 1.0, 0.0]
fluid_velocity = true
[particles.list.orientation]
axis = [0.0, 0.0, 1.0]
angle = 0.3
[particles.list.material]
law = "neo_hooke"
mu = 5.0
lambda = 50.0
[integrator]
type = "imex"
dt = 0.001
dt_max = 0.01
[end]
t_end = 1.0
max_steps = 1000
[output]
every = 0.1
vtk = true
"#;

/// A box with injected particles: quiescent fluid, planar walls, a disc, random orientations,
/// Mooney–Rivlin, adaptive Stokesian.
const INJECTED: &str = r#"[flow]
type = "quiescent"
[fluid]
viscosity = 1.0
density = 1.0
gravity = [0.0, 0.0, -9.81]
[boundary]
type = "planes"
contact_radius = 0.1
[[boundary.walls]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, -1.0]
rule = "stick"
[[boundary.walls]]
name = "lid"
point = [0.0, 0.0, 5.0]
normal = [0.0, 0.0, 1.0]
rule = "exit"
[particles]
density = 3.0
drag = "stokes_sphere"
[particles.inject]
count = 20
semi_axes = [1.0, 1.0, 0.5]
random_orientation = true
fluid_velocity = false
[particles.inject.region]
type = "disc"
centre = [0.0, 0.0, 2.0]
normal = [0.0, 0.0, 1.0]
radius = 1.5
[particles.inject.material]
law = "mooney_rivlin"
mu1 = 2.0
mu2 = 1.0
lambda = 30.0
[integrator]
type = "stokesian_radau5"
tol = 1e-6
dt = 0.01
overdamped = true
[end]
t_end = 2.0
[output]
every = 0.5
"#;

/// Replacement values: bad numbers, extreme numbers, wrong types.
const VALUES: [&str; 17] = [
    "nan",
    "inf",
    "-inf",
    "-1.0",
    "0.0",
    "1e308",
    "-1e308",
    "1e-320",
    "\"text\"",
    "true",
    "[1.0]",
    "[1.0, 2.0]",
    "[1.0, 2.0, 3.0, 4.0]",
    "[nan, 1.0, 1.0]",
    "[1e308, 1e308, 1e308]",
    "{ a = 1 }",
    "-5",
];

#[derive(Debug, Clone)]
enum Mutation {
    /// Set the value of the line's key.
    Value(&'static str),
    /// Remove the line.
    Remove,
    /// Add `bogus_key = 1` to the line's table.
    Unknown,
}

/// Lines of `text` that hold `key = value`.
fn key_lines(text: &str) -> Vec<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.contains(" = "))
        .map(|(i, _)| i)
        .collect()
}

fn mutate(text: &str, line: usize, m: &Mutation) -> (String, String) {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let key = lines[line].split(" = ").next().unwrap().trim().to_string();
    match m {
        Mutation::Value(v) => lines[line] = format!("{key} = {v}"),
        Mutation::Remove => {
            lines.remove(line);
        }
        Mutation::Unknown => {
            lines.insert(line + 1, "bogus_key = 1".to_string());
            return (lines.join("\n"), "bogus_key".to_string());
        }
    }
    (lines.join("\n"), key)
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        6 => proptest::sample::select(VALUES.to_vec()).prop_map(Mutation::Value),
        1 => Just(Mutation::Remove),
        1 => Just(Mutation::Unknown),
    ]
}

/// Apply `mutations` (on distinct lines of `base`) and check the error names one of their keys.
fn check(base: &str, mutations: &[(usize, Mutation)]) -> Result<(), TestCaseError> {
    let mut sorted = mutations.to_vec();
    // From the last line up, so that removing or adding a line does not move the others.
    sorted.sort_by_key(|(line, _)| std::cmp::Reverse(*line));
    let mut text = base.to_string();
    let mut keys = Vec::new();
    for (line, m) in &sorted {
        let (t, k) = mutate(&text, *line, m);
        text = t;
        keys.push(k);
    }
    let src = Source {
        file: "mutated.toml",
        text: &text,
    };
    match parse(&src, Path::new(".")) {
        Ok(_) => Ok(()),
        Err(SceneError::Invalid {
            file,
            line: at,
            column,
            key: named,
            message,
        }) => {
            prop_assert_eq!(file, "mutated.toml");
            prop_assert!(
                at >= 1 && at <= text.lines().count() + 1 && column >= 1,
                "{}:{}",
                at,
                column
            );
            // A removed key is named as missing, a wrong value by its dotted key; an error
            // that another key reports (a derived quantity) names the mutated key too.
            let names = |key: &String| {
                let leaf = key.rsplit('.').next().unwrap();
                named.split(['.', '[', ' ', ',']).any(|k| k == leaf) || message.contains(leaf)
            };
            prop_assert!(
                keys.iter().any(names),
                "mutating {:?} gave an error about `{}`: {}",
                sorted,
                named,
                message
            );
            Ok(())
        }
        Err(other) => Err(TestCaseError::fail(format!("not a scene error: {other}"))),
    }
}

/// Two distinct key lines of `base` with a mutation each.
fn two_mutations(base: &'static str) -> impl Strategy<Value = Vec<(usize, Mutation)>> {
    let lines = key_lines(base);
    (proptest::sample::subsequence(lines, 2), mutation(), mutation()).prop_map(|(l, a, b)| vec![(l[0], a), (l[1], b)])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Two keys broken at once: the error names one of them.
    #[test]
    fn listed_scene_errors_name_a_broken_key(m in two_mutations(LISTED)) {
        check(LISTED, &m)?;
    }

    /// The same for the injection scene.
    #[test]
    fn injected_scene_errors_name_a_broken_key(m in two_mutations(INJECTED)) {
        check(INJECTED, &m)?;
    }
}

#[test]
fn base_scenes_are_valid() {
    for text in [LISTED, INJECTED] {
        let src = Source {
            file: "base.toml",
            text,
        };
        parse(&src, Path::new(".")).unwrap();
    }
}

/// Every key of both base scenes, with every mutation: the exhaustive version of the property
/// (16 values + removal + unknown key, on each of ~70 lines).
#[test]
fn every_key_every_mutation() {
    for base in [LISTED, INJECTED] {
        for line in key_lines(base) {
            let all = VALUES
                .iter()
                .map(|v| Mutation::Value(v))
                .chain([Mutation::Remove, Mutation::Unknown]);
            for m in all {
                check(base, &[(line, m)]).unwrap();
            }
        }
    }
}

/// Vectors of the wrong length are errors naming the key (a four-component `semi_axes`,
/// `position` or `gravity` used to validate, the rest dropped).
#[test]
fn vectors_of_the_wrong_length_are_refused() {
    for (from, to, key) in [
        (
            "semi_axes = [1.0, 0.5, 0.5]",
            "semi_axes = [1.0, 0.5, 0.5, 2.0]",
            "semi_axes",
        ),
        ("position = [0.0, 1.0, 0.0]", "position = [0.0, 1.0]", "position"),
        (
            "gravity = [0.0, -1.0, 0.0]",
            "gravity = [0.0, -1.0, 0.0, 7.0]",
            "gravity",
        ),
    ] {
        assert!(LISTED.contains(from), "{from}");
        let text = LISTED.replace(from, to);
        let src = Source {
            file: "long.toml",
            text: &text,
        };
        match parse(&src, Path::new(".")) {
            Err(SceneError::Invalid {
                key: named, message, ..
            }) => {
                assert!(
                    named.contains(key) || message.contains(key),
                    "{to}: `{named}`: {message}"
                );
                assert!(message.contains("expected 3 numbers"), "{to}: {message}");
            }
            other => panic!("{to}: {:?}", other.map(|s| s.count())),
        }
    }
}

/// Laws, drag models and integrators are built by name through the library's registries: an
/// unknown name is refused at the key that names it, listing the registered names, and a
/// parameter the model does not take, a missing one or one of the wrong kind at its own key.
#[test]
fn models_by_name_are_refused_at_their_keys() {
    for (from, to, key, says) in [
        (
            "law = \"neo_hooke\"",
            "law = \"neo_hook\"",
            "particles.list[0].material.law",
            "\"neo_hooke\"",
        ),
        (
            "law = \"neo_hooke\"",
            "law = 3",
            "particles.list[0].material.law",
            "must be a name",
        ),
        (
            "mu = 5.0",
            "mu = \"5\"",
            "particles.list[0].material.mu",
            "must be a number",
        ),
        (
            "mu = 5.0",
            "mu1 = 5.0",
            "particles.list[0].material.mu1",
            "does not take `mu1`",
        ),
        (
            "lambda = 50.0",
            "",
            "particles.list[0].material.lambda",
            "needs `lambda`",
        ),
        (
            "drag = \"brenner\"",
            "drag = \"oseen\"",
            "particles.drag",
            "\"stokes_sphere\"",
        ),
        (
            "type = \"imex\"",
            "type = \"euler\"",
            "integrator.type",
            "\"radau_iia\"",
        ),
        (
            "dt = 0.001",
            "dt = 0.001\ntol = 1e-6",
            "integrator.tol",
            "`imex_paper` does not take `tol`",
        ),
        (
            "dt = 0.001",
            "dt = 0.001\noverdamped = true",
            "integrator.overdamped",
            "does not take",
        ),
        ("dt = 0.001", "", "integrator.dt", "needs `dt`"),
    ] {
        assert!(LISTED.contains(from), "{from}");
        let text = LISTED.replacen(from, to, 1);
        refused_at(&text, key, says, to);
    }
    // The scheme's name `imex_paper` (the scene above writes the earlier `imex`; errors name
    // it `imex_paper`, above) and a drag table are read.
    for (from, to) in [
        ("type = \"imex\"", "type = \"imex_paper\""),
        ("drag = \"brenner\"", "drag = { model = \"stokes_sphere\" }"),
    ] {
        let text = LISTED.replacen(from, to, 1);
        assert!(
            parse(
                &Source {
                    file: "named.toml",
                    text: &text
                },
                Path::new(".")
            )
            .is_ok(),
            "{to}"
        );
    }
}

/// Issue 38, item 6: the TOML reader's errors are named by the dotted path of the key they
/// are about. A duplicate key or table was named ``` `` ``` or by its bare leaf; the path
/// counts arrays of tables (`particles.list[0]`) and inline tables.
#[test]
fn toml_errors_name_the_dotted_key_path() {
    for (from, to, key, says) in [
        (
            "viscosity = 1.0",
            "viscosity = 1.0\nviscosity = 2.0",
            "fluid.viscosity",
            "duplicate key",
        ),
        ("[boundary]", "[fluid]\n[boundary]", "fluid", "duplicate key"),
        ("seed = 3", "seed = 3\nseed = 4", "seed", "duplicate key"),
        (
            "mu = 5.0",
            "mu = 5.0\nmu = 6.0",
            "particles.list[0].material.mu",
            "duplicate key",
        ),
        (
            "semi_axes = [1.0, 0.5, 0.5]",
            "semi_axes = [1.0, 0.5, 0.5]\nmaterial = { law = \"rigid\", law = \"rigid\" }",
            "particles.list[0].material.law",
            "duplicate key",
        ),
        (
            "radius = 10.0\nmean",
            "radius = \"ten\"\nmean",
            "flow.radius",
            "invalid type",
        ),
        (
            "rule = \"stick\"",
            "rule = \"stick\"\nrule = \"exit\"",
            "boundary.walls[0].rule",
            "duplicate key",
        ),
        // Issue 39, item 7: misspelled and missing keys.
        (
            "viscosity = 1.0\ndensity = 1.0\ngravity = [0.0, -1.0, 0.0]",
            "viscosty = 1.0\ndensity = 1.0\ngravity = [0.0, -1.0, 0.0]",
            "fluid.viscosty",
            "unknown field",
        ),
        ("t_end = 1.0", "t_ed = 1.0", "end.t_ed", "unknown field"),
        ("t_end = 1.0\n", "", "end.t_end", "missing field"),
        // Issue 61: a missing table of the document is named alone, not after the file's first
        // key (`seed = 3` made it `seed.end`).
        ("[end]\nt_end = 1.0\nmax_steps = 1000\n", "", "end", "missing field"),
        (
            "angle = 0.3",
            "angel = 0.3",
            "particles.list[0].orientation.angel",
            "unknown field",
        ),
        (
            "angle = 0.3",
            "",
            "particles.list[0].orientation.angle",
            "missing field",
        ),
    ] {
        let base = if LISTED.contains(from) { LISTED } else { INJECTED };
        assert!(base.contains(from), "{from}");
        let text = base.replacen(from, to, 1);
        refused_at(&text, key, says, to);
    }
}

/// `text` must be refused as a scene error at `key` whose message contains `says` (`edit` names
/// the edit that made it, for the failure message).
fn refused_at(text: &str, key: &str, says: &str, edit: &str) {
    match parse(
        &Source {
            file: "edited.toml",
            text,
        },
        Path::new("."),
    ) {
        Err(SceneError::Invalid {
            key: named, message, ..
        }) => {
            assert_eq!(named, key, "{edit}: {message}");
            assert!(message.contains(says), "{edit}: {message}");
        }
        other => panic!("{edit}: {:?}", other.map(|s| s.count())),
    }
}
