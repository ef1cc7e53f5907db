"""Scenes from files and dicts: the command's validation, its errors, and round trips."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

import pseudorigid as pr

ANALYTIC = ["oblate_shear.toml", "shear_injection.toml", "phase_boundary.toml", "pipe_fibre.toml"]


@pytest.mark.parametrize("name", ANALYTIC)
def test_shipped_scene_round_trip(root, name):
    s = pr.Scene.from_toml(root / "scenes" / name)
    d = s.to_dict()
    s2 = pr.Scene.from_dict(d)
    assert s2.to_dict() == d
    s3 = pr.Scene.from_text(s2.to_toml())
    assert s3.to_toml() == s2.to_toml()
    assert s3.count == s.count and s3.seed == s.seed
    np.testing.assert_array_equal(s3.frame_times, s.frame_times)


def random_scene(rng: random.Random) -> dict:
    ratio = rng.uniform(1.0, 4.0)
    material = rng.choice(
        [
            {"law": "rigid"},
            {"law": "neo_hooke", "mu": rng.uniform(0.1, 10.0), "lambda": rng.uniform(10.0, 1e4)},
            {"law": "mooney_rivlin", "mu1": rng.uniform(0.1, 5.0), "mu2": rng.uniform(0.0, 5.0), "lambda": 1e3},
        ]
    )
    return {
        "seed": rng.randrange(0, 2**63),
        "flow": {"type": rng.choice(["shear", "planar_extension"]), "rate": rng.uniform(0.1, 10.0)},
        "fluid": {"viscosity": rng.uniform(0.1, 2.0), "density": 1.0},
        "particles": {
            "density": rng.uniform(0.5, 2.0),
            "inject": {
                "count": rng.randrange(1, 1000),
                "semi_axes": [ratio, 1.0, rng.uniform(0.3, 1.0)],
                "random_orientation": True,
                "region": {"type": "point", "at": [rng.uniform(-1, 1), 0.0, 0.0]},
                "material": material,
            },
        },
        "integrator": {"type": "stokesian", "tol": 10 ** rng.uniform(-10, -4), "dt": 1e-3},
        "end": {"t_end": rng.uniform(0.5, 20.0)},
        "output": {"every": 0.5, "vtk": rng.random() < 0.5},
    }


def test_property_dict_scene_toml_scene():
    """dict -> Scene -> TOML -> Scene gives back the dict exactly, floats bit for bit."""
    rng = random.Random(21)
    for _ in range(50):
        d = random_scene(rng)
        s = pr.Scene.from_dict(d)
        assert s.to_dict() == d
        again = pr.Scene.from_text(s.to_toml())
        assert again.to_dict() == d
        assert again.count == d["particles"]["inject"]["count"]


def test_the_earlier_name_of_scene_error_still_catches_it() -> None:
    assert pr.StudyError is pr.SceneError
    with pytest.raises(pr.StudyError):
        pr.Scene.from_text("seed = -1\n")


def scene_error(d: dict) -> pr.SceneError:
    with pytest.raises(pr.SceneError) as info:
        pr.Scene.from_dict(d)
    assert isinstance(info.value, pr.PseudorigidError) and isinstance(info.value, ValueError)
    return info.value


@pytest.mark.parametrize(
    "path, value, key",
    [
        (("flow", "rate"), math.nan, "flow.rate"),
        (("flow", "rate"), math.inf, "flow.rate"),
        (("fluid", "viscosity"), -1.0, "fluid.viscosity"),
        (("flow", "rate"), "fast", "rate"),
        (("particles", "inject", "count"), 1.5, "count"),
        (("particles", "inject", "semi_axes"), [1.0, math.nan, 1.0], "particles.inject.semi_axes"),
        (("particles", "inject", "material", "mu"), -2.5, "particles.inject.material"),
        (("fluid", "viscosity"), [1.0], "viscosity"),
        (("end", "t_end"), 0.0, "end.t_end"),
    ],
)
def test_bad_values_name_their_key(small_scene, path, value, key):
    d = small_scene
    node = d
    for p in path[:-1]:
        node = node[p]
    node[path[-1]] = value
    e = scene_error(d)
    assert key in e.key and e.file == "<dict>" and e.line >= 1 and e.column >= 1, (e.key, str(e))
    assert f"`{e.key}`" in str(e)


def test_unknown_and_missing_keys(small_scene):
    small_scene["flow"]["speed"] = 2.0
    assert "speed" in str(scene_error(small_scene))
    del small_scene["flow"]["speed"]
    del small_scene["fluid"]
    assert "fluid" in str(scene_error(small_scene))


def test_values_python_cannot_express_in_toml(small_scene):
    e = scene_error({**small_scene, "flow": {"type": "shear", "rate": object()}})
    assert e.key == "flow.rate"
    e = scene_error({**small_scene, "seed": 2**70})
    assert e.key == "seed"
    e = scene_error({**small_scene, "end": {1: 2.0}})
    assert e.key == "end"
    assert scene_error([]).key == ""  # type: ignore[arg-type]


def test_numpy_values_are_accepted(small_scene):
    small_scene["particles"]["inject"]["semi_axes"] = np.array([0.7, 0.3, 0.7])
    small_scene["flow"]["rate"] = np.float32(0.5)
    small_scene["particles"]["inject"]["count"] = np.int64(3)
    s = pr.Scene.from_dict(small_scene)
    assert s.count == 3 and s.to_dict()["flow"]["rate"] == 0.5


def test_scene_file_errors_carry_line_and_column(tmp_path, root):
    text = (root / "scenes" / "shear_injection.toml").read_text().replace("viscosity = 1.0", "viscosity = -1.0")
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(pr.SceneError) as info:
        pr.Scene.from_toml(f)
    e = info.value
    line = next(i for i, l in enumerate(text.splitlines(), 1) if l.startswith("viscosity = -1.0"))
    assert (e.file, e.line, e.column, e.key) == (str(f), line, 13, "fluid.viscosity")
    assert str(e).startswith(f"{f}:{line}:13: `fluid.viscosity`")


def test_missing_files(tmp_path, small_scene):
    with pytest.raises(FileNotFoundError):
        pr.Scene.from_toml(tmp_path / "nope.toml")
    with pytest.raises(FileNotFoundError):
        pr.FoamFlow(tmp_path / "no-case")
    with pytest.raises(FileNotFoundError):
        pr.load_results(tmp_path / "no-run")
    # A case named inside a scene is a value of the scene: reported at its key, as the command does.
    d = {**small_scene, "flow": {"type": "openfoam", "case": "no-case"}}
    with pytest.raises(pr.SceneError, match="not found") as info:
        pr.Scene.from_dict(d, base=tmp_path)
    assert info.value.key == "flow.case"


def test_bad_run_arguments(tmp_path, small_scene):
    s = pr.Scene.from_dict(small_scene)
    with pytest.raises(pr.ParameterError):
        pr.run(s, tmp_path, shard=(3, 2))
    with pytest.raises(pr.ParameterError):
        pr.run(s, tmp_path, checkpoint_every=math.nan)
    with pytest.raises(pr.ParameterError):
        pr.run(s, tmp_path, progress="yes")  # type: ignore[arg-type]
    with pytest.raises(pr.ParameterError):
        pr.run(123, tmp_path)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        pr.run(s, tmp_path, threads="two")  # type: ignore[arg-type]


def test_models_resolve_by_name_and_unknown_names_name_their_key():
    """Laws, drag models and integrators are built through the library's registries: a drag
    model by name and the earlier integrator spelling `stokesian` read, and an unknown name is
    refused at its key."""
    d = random_scene(random.Random(7))
    d["particles"]["drag"] = "stokes_sphere"
    pr.Scene.from_dict(d)

    def refused(edit) -> str:
        broken = random_scene(random.Random(7))
        edit(broken)
        with pytest.raises(pr.SceneError) as info:
            pr.Scene.from_dict(broken)
        return info.value.key

    law = {"law": "neo_hook", "mu": 1.0, "lambda": 10.0}
    assert refused(lambda b: b["particles"]["inject"].update(material=law)) == "particles.inject.material.law"
    assert refused(lambda b: b["particles"].update(drag="oseen")) == "particles.drag"
    assert refused(lambda b: b["integrator"].update(type="euler")) == "integrator.type"
