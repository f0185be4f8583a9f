"""Every Python block of docs/python.md and docs/mitsuba.md runs as written: a page's blocks in
order, in one interpreter, in a temporary folder (so that they neither need the repository root
as the working directory nor write into it), with NPF_SOURCE naming the source tree, as the pages
say. docs/mitsuba.md's blocks are skipped where Mitsuba is not installed or Dr.Jit would find no
usable LLVM (npf.mitsuba.check_llvm), so that the unit suite passes without them."""
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def python_blocks(page):
    return re.findall(r"^```python\n(.*?)^```", (REPO / "docs" / page).read_text(), flags=re.S | re.M)


def mitsuba_missing():
    probe = "import mitsuba, npf.mitsuba; npf.mitsuba.check_llvm()"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    return (done.stderr.strip().splitlines() or ["?"])[-1] if done.returncode != 0 else None


@pytest.mark.parametrize("page", ["python.md", "mitsuba.md"])
def test_doc_blocks_run_as_written(page, tmp_path):
    blocks = python_blocks(page)
    assert blocks, "no Python block in docs/" + page
    if page == "mitsuba.md":
        why = mitsuba_missing()
        if why:
            pytest.skip("Mitsuba 3 is not usable here: " + why)
    script = tmp_path / "blocks.py"
    script.write_text("\n".join(blocks))
    env = dict(os.environ, NPF_SOURCE=str(REPO))
    env["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in env.get("PYTHONPATH", "").split(os.pathsep) if p)
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=900)
    assert done.returncode == 0, "docs/{}: {}".format(page, done.stderr[-3000:])
