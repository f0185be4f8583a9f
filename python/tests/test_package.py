"""The Python package npf (python/npf, docs/python.md): the numbers `npf eval` prints, batched
calls over numpy arrays (stored channels, shared and per-pair wavelengths), sampling, conversion
and editing with the command line's settings (the same bytes), and errors as npf.Error naming
the file or argument and the problem.

Run by ctest as `python.package` with PYTHONPATH at the build tree's package and NPF_EXECUTABLE
the npf command of the same build.
"""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import npf

REPO = Path(__file__).resolve().parents[2]
SHIPPED = REPO / "data" / "materials" / "ilm_l3_37_metallic_rgb.bsdf"
COPPER_RECIPE = REPO / "configs" / "materials" / "brushed_copper.yaml"
NPF = os.environ.get("NPF_EXECUTABLE", str(REPO / "build" / "tools" / "npf" / "npf"))
# A preview conversion of the shipped file, fast: the factors alone, no prediction or error pass.
FAST = dict(preset="preview", error_pairs=0, no_predict=True, detail="none")


def run_npf(*args, stdin=None):
    done = subprocess.run([NPF, *map(str, args)], input=stdin, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def hemisphere(rng, n):
    a, b = rng.random(n), rng.random(n)
    s = np.sqrt(a)
    return np.stack([s * np.cos(2 * np.pi * b), s * np.sin(2 * np.pi * b), np.sqrt(1.0 - a)], axis=1)


def npf_eval_lines(path, wi, wo, *flags):
    """`npf eval` of the pairs: one line of numbers per pair (its header and comments dropped)."""
    text = "\n".join(" ".join(repr(float(x)) for x in np.r_[a, b]) for a, b in zip(wi, wo)) + "\n"
    out = run_npf("eval", path, *flags, stdin=text)
    return [line for line in out.splitlines() if not line.startswith("#")]


def printed(*columns):
    """Rows of numbers as npf eval prints them (%.9g, space-separated): equal text, equal numbers."""
    rows = np.column_stack(columns)
    return [" ".join("%.9g" % x for x in row) for row in rows]


@pytest.fixture(scope="module")
def ilm_exr(tmp_path_factory):
    path = tmp_path_factory.mktemp("ilm") / "ilm.exr"
    npf.convert(SHIPPED, path, **FAST)
    return path


@pytest.fixture(scope="module")
def copper_exr(tmp_path_factory):
    """A small spectral, anisotropic conversion of the brushed copper recipe (8 wavelengths)."""
    path = tmp_path_factory.mktemp("copper") / "copper.exr"
    npf.convert(COPPER_RECIPE, path, **FAST, wavelengths="400:700:8", grid=(16, 8, 16, 32), g_grid=(16, 8))
    return path


@pytest.fixture
def rng():
    return np.random.default_rng(7)


def test_every_source_gives_what_npf_eval_prints(ilm_exr, rng):
    wi, wo = hemisphere(rng, 40), hemisphere(rng, 40)
    wi[3] = [0.2, 0.1, -0.5]  # below the horizon: 0, as npf eval
    for path in (SHIPPED, ilm_exr, COPPER_RECIPE):
        values = npf.open(path).eval(wi, wo)
        assert values.shape[0] == 40 and values.shape[1] == len(npf.open(path).channels)
        assert printed(values) == npf_eval_lines(path, wi, wo)
        assert np.all(values[3] == 0.0)


def test_cos_and_pdf_are_npf_evals(ilm_exr, rng):
    m = npf.open(ilm_exr)
    wi, wo = hemisphere(rng, 30), hemisphere(rng, 30)
    assert printed(m.eval(wi, wo, cos=True), m.pdf(wi, wo)) == npf_eval_lines(ilm_exr, wi, wo, "--cos", "--pdf")


def test_wavelengths_shared_and_per_pair(copper_exr, rng):
    m = npf.open(copper_exr)
    assert not m.is_rgb and len(m.wavelengths) == 8 and not m.info["isotropic"]
    n = 50
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    stored = m.eval(wi, wo)
    assert stored.shape == (n, 8)
    # Stored wavelengths asked for by value give the stored channels.
    np.testing.assert_array_equal(m.eval(wi, wo, wavelengths=m.wavelengths), stored)
    shared = [420.0, 555.5, 690.0]
    assert printed(m.eval(wi, wo, wavelengths=shared)) == npf_eval_lines(copper_exr, wi, wo, "--wavelengths", "420,555.5,690")
    # Hero wavelengths per pair: each row what a call with that row's wavelengths gives.
    hero = 400.0 + 300.0 * rng.random((n, 4))
    per_pair = m.eval(wi, wo, wavelengths=hero)
    assert per_pair.shape == (n, 4)
    for i in range(0, n, 7):
        np.testing.assert_array_equal(per_pair[i], m.eval(wi[i], wo[i], wavelengths=hero[i])[0])


def test_bad_wavelengths_are_errors_on_every_source(copper_exr, rng):
    wi, wo = hemisphere(rng, 8), hemisphere(rng, 8)
    hero = np.full((8, 4), 500.0)
    hero[5, 2] = np.nan
    for path in (copper_exr, COPPER_RECIPE):
        with pytest.raises(npf.Error, match=r"wavelengths\[5, 2\]: not a positive number"):
            npf.open(path).eval(wi, wo, wavelengths=hero)
    with pytest.raises(npf.Error, match=r"wavelengths\[0, 1\]"):
        npf.open(copper_exr).sample(wi, rng.random((8, 2)), wavelengths=[500.0, -3.0])


def test_results_do_not_depend_on_threads(copper_exr, rng):
    m = npf.open(copper_exr)
    wi, wo = hemisphere(rng, 5000), hemisphere(rng, 5000)
    hero = 400.0 + 300.0 * rng.random((5000, 4))
    np.testing.assert_array_equal(m.eval(wi, wo, wavelengths=hero, threads=1), m.eval(wi, wo, wavelengths=hero, threads=2))
    u = rng.random((5000, 2))
    for a, b in zip(m.sample(wi, u, threads=1), m.sample(wi, u, threads=2)):
        np.testing.assert_array_equal(a, b)


def test_sample_weight_is_value_over_pdf(rng):
    for path in (SHIPPED, COPPER_RECIPE):
        m = npf.open(path)
        wi, u = hemisphere(rng, 400), rng.random((400, 2))
        wo, pdf, weight = m.sample(wi, u)
        drawn = pdf > 0
        assert drawn.mean() > 0.5
        assert np.all(weight[~drawn] == 0) and np.all(wo[~drawn] == 0)
        np.testing.assert_allclose(np.linalg.norm(wo[drawn], axis=1), 1.0, rtol=1e-6)
        np.testing.assert_allclose(m.pdf(wi[drawn], wo[drawn]), pdf[drawn], rtol=1e-5)
        np.testing.assert_allclose(weight[drawn], m.eval(wi[drawn], wo[drawn], cos=True) / pdf[drawn, None], rtol=1e-5,
                                   atol=1e-7)


def test_one_direction_broadcasts(ilm_exr, rng):
    m = npf.open(ilm_exr)
    wo = hemisphere(rng, 10)
    np.testing.assert_array_equal(m.eval([0, 0, 1], wo), m.eval(np.tile([0.0, 0.0, 1.0], (10, 1)), wo))
    # Directions are normalised on reading, as npf eval reads them.
    np.testing.assert_array_equal(m.eval([0, 0, 3], 2.5 * wo), m.eval([0, 0, 1], wo))


def test_info_describes_the_material(ilm_exr):
    m = npf.open(ilm_exr)
    assert m.channels == ["R", "G", "B"] and m.is_rgb
    assert m.info["format"] == "npf-exr" and m.info["batched"]
    assert npf.open(SHIPPED).info["format"] == "rgl"
    assert "npf-exr" in repr(m)


def test_errors_name_the_file_or_argument_and_the_problem(ilm_exr, tmp_path):
    with pytest.raises(npf.Error) as e:
        npf.open(tmp_path / "missing.bsdf")
    assert e.value.source == str(tmp_path / "missing.bsdf") and "not found" in e.value.problem
    garbage = tmp_path / "garbage.bsdf"
    garbage.write_bytes(b"not a material at all")
    with pytest.raises(npf.Error, match="garbage.bsdf"):
        npf.open(garbage)
    m = npf.open(ilm_exr)
    with pytest.raises(npf.Error, match=r"wi\[1\]: a direction of zero length"):
        m.eval([[0, 0, 1], [0, 0, 0]], [[0, 0, 1], [0, 0, 1]])
    with pytest.raises(npf.Error, match=r"wo\[0\]"):
        m.eval([0, 0, 1], [np.nan, 0, 1])
    with pytest.raises(npf.Error, match=r"wi\[2\]: a direction of zero length or not finite"):
        m.pdf([[0, 0, 1], [0, 0, 1], [np.inf, 0, 1]], [0, 0, 1])
    # Components far from 1 are directions like any other (normalised as npf eval does).
    np.testing.assert_array_equal(m.eval([0, 0, 1e300], [1e-300, 0, 1e-300]), m.eval([0, 0, 1], [1, 0, 1]))
    with pytest.raises(npf.Error, match=r"u\[1, 0\]: not a uniform number in \[0, 1\)"):
        m.sample([0, 0, 1], [[0.5, 0.5], [np.nan, 0.5]])
    with pytest.raises(npf.Error, match="expected an \\(N, 3\\) array"):
        m.eval(np.zeros((4, 2)), np.zeros((4, 3)))
    with pytest.raises(npf.Error, match="3 and 4 directions"):
        m.eval(np.ones((3, 3)), np.ones((4, 3)))
    with pytest.raises(npf.Error, match="holds RGB data"):
        m.eval([0, 0, 1], [0, 0, 1], wavelengths=[500.0])
    with pytest.raises(npf.Error) as e:
        npf.convert(SHIPPED, tmp_path / "x.exr", preset="fastest")
    assert e.value.source == "preset"
    with pytest.raises(npf.Error, match="not a conversion setting"):
        npf.convert(SHIPPED, tmp_path / "x.exr", colour="red")
    with pytest.raises(npf.Error, match="not an edit"):
        npf.edit(ilm_exr, tmp_path / "y.exr", paint_it_black=True)
    with pytest.raises(npf.Error, match="not an NPF factor texture"):
        npf.edit(SHIPPED, tmp_path / "y.exr", sharpen=2)
    assert sorted(os.listdir(tmp_path)) == ["garbage.bsdf"]  # nothing written by a failed call


def test_convert_writes_what_npf_convert_writes(tmp_path):
    settings = dict(FAST, threads=1)
    report = npf.convert(SHIPPED, tmp_path / "py.exr", **settings)
    run_npf("convert", SHIPPED, "-o", tmp_path / "cli.exr", "--preset", "preview", "--error-pairs", "0", "--no-predict",
            "--detail", "none", "--threads", "2", "--quiet")
    assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert report["output_bytes"] == (tmp_path / "py.exr").stat().st_size
    assert report["d_rank"] >= 1 and report["channel_count"] == 3 and not report["has_detail"]
    fractions = []
    npf.convert(SHIPPED, tmp_path / "progress.exr", progress=fractions.append, **FAST)
    assert fractions and fractions[-1] == 1.0 and fractions == sorted(fractions)


def test_an_exception_in_progress_stops_the_conversion_and_writes_nothing(tmp_path):
    # As Ctrl-C does (KeyboardInterrupt through the same path): the conversion unwinds, no output.
    class Stop(Exception):
        pass

    def stop_midway(fraction):
        if fraction > 0.05:
            raise Stop()

    with pytest.raises(Stop):
        npf.convert(SHIPPED, tmp_path / "stopped.exr", progress=stop_midway, **FAST)
    assert os.listdir(tmp_path) == []


def test_edit_writes_what_npf_edit_writes(ilm_exr, tmp_path):
    report = npf.edit(ilm_exr, tmp_path / "py.exr", diffuse_srgb=(0.8, 0.1, 0.1), sharpen=1.5)
    run_npf("edit", ilm_exr, "-o", tmp_path / "cli.exr", "--diffuse-srgb", "0.8,0.1,0.1", "--sharpen", "1.5")
    assert (tmp_path / "py.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()
    assert len(report["steps"]) == 2 and report["history"] == ["edit_001", "edit_002"]
    dry = npf.edit(ilm_exr, dry_run=True, sharpen=1.5)
    assert dry["output"] == "" and len(dry["steps"]) == 1
    assert "sharpen" in npf.edit_flags() and "preset" in npf.convert_settings()


def test_convert_judges_the_lightings_asked_for(tmp_path):
    # light= replaces the prediction's set; the report gives each lighting (PSNR, floor) and the worst.
    report = npf.convert(SHIPPED, tmp_path / "lit.exr", preset="preview", error_pairs=0, detail="none",
                         light=["studio", "directional"])
    each = report["predicted_psnr_by_lighting"]
    assert list(each) == ["studio", "directional"]
    assert report["predicted_psnr_db"] == min(psnr for psnr, _ in each.values())
    assert each["directional"][1] == float("inf")  # no Monte Carlo, no noise floor
    with pytest.raises(npf.Error, match="spotlight"):
        npf.convert(SHIPPED, tmp_path / "x.exr", preset="preview", light="spotlight")


def test_factor_tables_are_the_files_and_the_samplers(ilm_exr, copper_exr):
    # What npf.mitsuba shades with: the grids' sizes agree with the arrays, and the sampler's
    # densities (1/sr per D cell) integrate to 1 over the cells' solid angles.
    for path in (ilm_exr, copper_exr):
        m = npf.open(path)
        t = m.factor_tables()
        C = len(m.channels)
        assert t["F"].shape == (C, t["f_theta"]) and t["rho_d"].shape == (C,)
        assert t["D"]["basis"].shape == (t["D"]["rank"], t["d_theta"] * t["d_phi"])
        assert t["G"]["weights"].shape == (C, t["G"]["rank"])
        assert (t["channels"] == "rgb") == m.is_rgb and len(t["wavelengths_nm"]) == len(m.wavelengths)
        s = t["sampler"]
        omega = 2 * np.diff(s["half_sin2"]) * 2 * np.pi / t["d_phi"]
        assert abs(np.sum(s["density"].reshape(t["d_theta"], t["d_phi"]) * omega[:, None]) - 1) < 1e-5
        assert np.all(s["alias"] < t["d_theta"] * t["d_phi"]) and 0 <= t["diffuse_probability"] < 1
    with pytest.raises(npf.Error, match="not an NPF factor texture"):
        npf.open(REPO / "data" / "materials" / "ilm_l3_37_metallic_rgb.bsdf").factor_tables()
