"""The MaterialX node definition of the NPF BSDF (configs/materialx/, docs/materialx.md).

Checks, with the MaterialX Python package from PyPI (`pip install materialx`, 1.38.10 and
1.39.x tested) and the standard data libraries its wheel ships:

- the library (configs/materialx/npf_bsdf.mtlx) and the example material document validate;
- ND_npf_bsdf has exactly the documented interface (inputs, types, defaults, output) and no
  implementation;
- the example's npf_bsdf node resolves to ND_npf_bsdf, and its material reaches it through a
  `surface` node;
- deliberately broken documents (a wrong input type, an unknown input, a wrong output type, a
  BSDF connected where a surfaceshader is expected) fail validation, so these checks can fail.

MaterialX missing is a failure, not a skip: CI installs it.
"""

from pathlib import Path

import pytest

try:
    import MaterialX as mx
except ImportError as error:  # reported by every test through the fixtures below
    mx = None
    MX_IMPORT_ERROR = error
else:
    MX_IMPORT_ERROR = None

REPO = Path(__file__).resolve().parents[2]
LIBRARY = REPO / "configs" / "materialx" / "npf_bsdf.mtlx"
EXAMPLE = REPO / "configs" / "materialx" / "example_npf_material.mtlx"


def require_materialx():
    if mx is None:
        pytest.fail(
            "the MaterialX Python package is not importable ({}): install it with "
            "`pip install materialx` (CI does); these tests do not skip without it".format(MX_IMPORT_ERROR),
            pytrace=False,
        )


@pytest.fixture(scope="session")
def stdlib():
    """MaterialX's standard data libraries (stdlib, pbrlib, ...), as shipped in the wheel."""
    require_materialx()
    doc = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), doc)
    assert doc.getNodeDef("ND_surface") is not None, "the standard libraries did not load"
    assert doc.getNodeDef("ND_surfacematerial") is not None, "the standard libraries did not load"
    return doc


@pytest.fixture(scope="session")
def library(stdlib):
    """Our library read into a document that imports the standard ones (its normal and tangent
    defaults name the stdlib geomprops Nworld and Tworld)."""
    assert LIBRARY.is_file(), "missing {}".format(LIBRARY)
    doc = mx.createDocument()
    doc.importLibrary(stdlib)
    mx.readFromXmlFile(doc, str(LIBRARY))
    return doc


def read_example(stdlib):
    assert EXAMPLE.is_file(), "missing {}".format(EXAMPLE)
    doc = mx.createDocument()
    doc.importLibrary(stdlib)
    mx.readFromXmlFile(doc, str(EXAMPLE))  # its xi:include brings in npf_bsdf.mtlx
    return doc


def document_with(library, body):
    """A document holding `body` (MaterialX elements) over the standard libraries and ours."""
    doc = mx.createDocument()
    doc.importLibrary(library)
    mx.readFromXmlString(doc, '<?xml version="1.0"?>\n<materialx version="1.38">\n' + body + "\n</materialx>\n")
    return doc


def test_materialx_is_importable():
    require_materialx()
    print("MaterialX", mx.getVersionString())


def test_library_validates(library):
    ok, message = library.validate()
    assert ok, "npf_bsdf.mtlx does not validate:\n" + message


def test_nodedef_interface(library):
    nodedefs = library.getMatchingNodeDefs("npf_bsdf")
    assert [nd.getName() for nd in nodedefs] == ["ND_npf_bsdf"]
    nd = library.getNodeDef("ND_npf_bsdf")
    assert nd.getNodeString() == "npf_bsdf"
    assert nd.getNodeGroup() == "pbr"
    assert nd.getAttribute("bsdf") == "R"  # reflection only, as the closure
    assert [(o.getName(), o.getType()) for o in nd.getOutputs()] == [("out", "BSDF")]

    inputs = [(i.getName(), i.getType()) for i in nd.getInputs()]
    assert inputs == [("weight", "float"), ("file", "filename"), ("normal", "vector3"), ("tangent", "vector3")]

    weight = nd.getInput("weight")
    assert weight.getValue() == pytest.approx(1.0)
    assert (weight.getAttribute("uimin"), weight.getAttribute("uimax")) == ("0.0", "1.0")
    assert not weight.hasDefaultGeomPropString()

    file_input = nd.getInput("file")
    assert file_input.getValueString() == ""
    assert file_input.getAttribute("uniform") == "true"  # one file per material, not per point
    assert not file_input.hasColorSpace()  # basis tables and weights, not an image

    for name, geomprop in (("normal", "Nworld"), ("tangent", "Tworld")):
        frame_input = nd.getInput(name)
        assert frame_input.getDefaultGeomPropString() == geomprop
        assert frame_input.getValueString() == ""
        assert frame_input.getAttribute("uniform") != "true"

    # No standard implementation: MaterialX's generators cannot build this node (docs/materialx.md).
    assert nd.getImplementation() is None
    assert library.getMatchingImplementations("ND_npf_bsdf") == []


def test_example_validates_and_resolves(stdlib):
    doc = read_example(stdlib)
    ok, message = doc.validate()
    assert ok, "example_npf_material.mtlx does not validate:\n" + message

    bsdf = doc.getNode("ilm_l3_37_metallic_bsdf")
    assert bsdf is not None and bsdf.getCategory() == "npf_bsdf" and bsdf.getType() == "BSDF"
    nodedef = bsdf.getNodeDef()
    assert nodedef is not None, "the example's npf_bsdf node does not resolve to a nodedef"
    assert nodedef.getName() == "ND_npf_bsdf"
    assert Path(nodedef.getSourceUri()).name == "npf_bsdf.mtlx"  # from the xi:include
    file_input = bsdf.getInput("file")
    assert file_input.getType() == "filename"
    assert file_input.getValueString() == "ilm_l3_37_metallic.exr"

    material = doc.getNode("ilm_l3_37_metallic")
    assert material is not None and material.getCategory() == "surfacematerial"
    assert material.getNodeDef().getName() == "ND_surfacematerial"
    shaders = mx.getShaderNodes(material)
    assert [s.getName() for s in shaders] == ["ilm_l3_37_metallic_surface"]
    surface = shaders[0]
    assert surface.getNodeDef().getName() == "ND_surface"
    assert surface.getInput("bsdf").getConnectedNode().getName() == "ilm_l3_37_metallic_bsdf"


def test_validate_alone_does_not_catch_a_missing_library(stdlib):
    # A node of an undeclared category validates: a pipeline must check getNodeDef() (or load
    # npf_bsdf.mtlx) itself. This is why the example's check above asks for the nodedef.
    doc = mx.createDocument()
    doc.importLibrary(stdlib)
    mx.readFromXmlString(
        doc,
        '<?xml version="1.0"?>\n<materialx version="1.38">\n'
        '<npf_bsdf name="b" type="BSDF"><input name="file" type="filename" value="x.exr" /></npf_bsdf>\n'
        "</materialx>\n",
    )
    ok, message = doc.validate()
    assert ok, message
    assert doc.getNode("b").getNodeDef() is None


GOOD_NODE = '<npf_bsdf name="b" type="BSDF"><input name="file" type="filename" value="x.exr" /></npf_bsdf>'

BROKEN = {
    "wrong input type": (
        '<npf_bsdf name="b" type="BSDF"><input name="weight" type="color3" value="1, 1, 1" /></npf_bsdf>',
        "Input 'weight' doesn't match declaration",
    ),
    "file as a string": (
        '<npf_bsdf name="b" type="BSDF"><input name="file" type="string" value="x.exr" /></npf_bsdf>',
        "Input 'file' doesn't match declaration",
    ),
    "unknown input": (
        '<npf_bsdf name="b" type="BSDF"><input name="roughness" type="float" value="0.2" /></npf_bsdf>',
        "Input 'roughness' doesn't match declaration",
    ),
    "wrong output type": (
        '<npf_bsdf name="b" type="surfaceshader"><input name="file" type="filename" value="x.exr" /></npf_bsdf>',
        "doesn't support this output type",
    ),
    "BSDF where a surfaceshader is expected": (
        GOOD_NODE + '<surfacematerial name="m" type="material">'
        '<input name="surfaceshader" type="surfaceshader" nodename="b" /></surfacematerial>',
        "Mismatched types in port connection",
    ),
}


def test_minimal_document_validates(library):
    # The control for the broken documents below: the same node, well formed, in a material.
    doc = document_with(
        library,
        GOOD_NODE + '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>'
        '<surfacematerial name="m" type="material">'
        '<input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>',
    )
    ok, message = doc.validate()
    assert ok, message
    assert doc.getNode("b").getNodeDef().getName() == "ND_npf_bsdf"


@pytest.mark.parametrize("case", sorted(BROKEN))
def test_broken_documents_fail_validation(library, case):
    body, expected = BROKEN[case]
    ok, message = document_with(library, body).validate()
    print(case, "->", message.strip())
    assert not ok, "a broken document ({}) validated".format(case)
    assert expected in message, message
