"""Hostile arguments to the Python package (issue 33): arrays of the wrong kind (objects, strings,
booleans, complex numbers, ragged lists), odd layouts (zero length, negative strides, Fortran
order, broadcast views), more pairs than one call takes, thread counts out of range and file names
that are not text. Each is an npf.Error naming the argument, or works exactly as its plain
equivalent; none is a numpy exception, a silent cast, another file or a killed process.
"""

import os
from pathlib import Path

import numpy as np
import pytest

import npf

REPO = Path(__file__).resolve().parents[2]
SHIPPED = REPO / "data" / "materials" / "ilm_l3_37_metallic_rgb.bsdf"
COPPER_RECIPE = REPO / "configs" / "materials" / "brushed_copper.yaml"

WI = np.array([[0.1, 0.2, 0.97]])
WO = np.array([[0.3, -0.1, 0.95]])


@pytest.fixture(scope="module")
def ilm():
    return npf.open(SHIPPED)


def raises_npf(source, fn):
    with pytest.raises(npf.Error) as e:
        fn()
    assert e.value.source == source, str(e.value)
    return e.value


@pytest.mark.parametrize("bad, what", [
    (np.array([[object(), 0, 1]], dtype=object), "expected real numbers, got an array of object"),
    (np.array([["a", "b", "c"]]), "expected real numbers, got an array of <U1"),
    (np.array([[1j, 0, 1]]), "expected real numbers, got an array of complex128"),
    (np.array([[True, False, True]]), "expected real numbers, got an array of bool"),
    ([[0, 0, 1], [0, 1]], "not an array of numbers"),
])
def test_arrays_of_the_wrong_kind_are_npf_errors(ilm, bad, what):
    for call in (lambda: ilm.eval(bad, WO), lambda: ilm.pdf(bad, WO), lambda: ilm.sample(bad, [[0.5, 0.5]])):
        e = raises_npf("wi", call)
        assert what in e.problem
    raises_npf("wo", lambda: ilm.eval(WI, bad))
    raises_npf("u", lambda: ilm.sample(WI, bad[:, :2] if isinstance(bad, np.ndarray) else bad))


def test_layouts_give_the_values_of_a_plain_array(ilm):
    rng = np.random.default_rng(3)
    wi = rng.normal(size=(50, 3))
    wi[:, 2] = np.abs(wi[:, 2]) + 0.1
    plain = ilm.eval(wi, WO)
    assert np.array_equal(ilm.eval(wi[::-1], WO), plain[::-1])                   # negative strides
    assert np.array_equal(ilm.eval(np.asfortranarray(wi), WO), plain)             # Fortran order
    assert np.array_equal(ilm.eval(wi[:, [0, 1, 2]].astype(np.float32), WO),     # another dtype
                          ilm.eval(wi.astype(np.float32).astype(np.float64), WO))
    assert np.array_equal(ilm.eval(np.broadcast_to(WI, (50, 3)), WO), np.repeat(ilm.eval(WI, WO), 50, axis=0))
    big = np.zeros((50, 6))
    big[:, ::2] = wi                                                              # a strided view
    assert np.array_equal(ilm.eval(big[:, ::2], WO), plain)


def test_zero_pairs_give_empty_results(ilm):
    assert ilm.eval(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0, 3)
    assert ilm.pdf(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)
    wo, pdf, weight = ilm.sample(np.zeros((0, 3)), np.zeros((0, 2)))
    assert wo.shape == (0, 3) and pdf.shape == (0,) and weight.shape == (0, 3)


def test_more_pairs_than_a_call_takes_are_refused_before_any_allocation(ilm):
    n = npf.MAX_PAIRS + 1
    huge = np.broadcast_to(WI, (n, 3))  # a view: no memory
    e = raises_npf("wi, wo", lambda: ilm.eval(huge, WO))
    assert "pairs in one call" in e.problem
    raises_npf("wi, wo", lambda: ilm.pdf(WI, np.broadcast_to(WO, (n, 3))))
    raises_npf("wi, u", lambda: ilm.sample(WI, np.broadcast_to(np.array([[0.5, 0.5]]), (n, 2))))


@pytest.mark.parametrize("threads", [-1, 1025, 10**12, True, 2.5, "4", None])
def test_thread_counts_out_of_range_are_refused(ilm, threads):
    raises_npf("threads", lambda: ilm.eval(WI, WO, threads=threads))
    raises_npf("threads", lambda: ilm.pdf(WI, WO, threads=threads))
    raises_npf("threads", lambda: ilm.sample(WI, [[0.5, 0.5]], threads=threads))


def test_wavelengths_of_the_wrong_kind_are_refused():
    copper = npf.open(COPPER_RECIPE)
    raises_npf("wavelengths", lambda: copper.eval(WI, WO, wavelengths=np.array(["500"])))
    raises_npf("wavelengths", lambda: copper.eval(WI, WO, wavelengths=[[500, 600], [1]]))
    assert copper.eval(WI, WO, wavelengths=np.array([500], dtype=np.int64)).shape == (1, 1)


def test_file_names_are_text_without_nul(tmp_path):
    as_bytes = npf.open(os.fsencode(str(SHIPPED)))
    assert as_bytes.path == str(SHIPPED)
    assert npf.open(SHIPPED).path == str(SHIPPED)   # os.PathLike
    e = raises_npf(repr(str(SHIPPED) + "\0.exr"), lambda: npf.open(str(SHIPPED) + "\0.exr"))
    assert "NUL" in e.problem
    raises_npf(repr(3), lambda: npf.open(3))
    out = tmp_path / "x.exr"
    with pytest.raises(npf.Error):
        npf.convert(SHIPPED, str(out) + "\0y", preset="preview", no_predict=True)
    assert list(tmp_path.iterdir()) == []
