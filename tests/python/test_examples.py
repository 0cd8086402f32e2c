"""The README's Python example and python/examples/remesh.py run."""
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import locus
from conftest import SOURCE_DIR


def readme_examples():
    text = (SOURCE_DIR / "README.md").read_text()
    return re.findall(r"<!-- python-example: (\S+) -->\n```python\n(.*?)\n```", text, re.S)


def test_readme_has_an_example():
    assert [name for name, _ in readme_examples()] == ["readme_session.py"]


@pytest.mark.parametrize("name,code", readme_examples())
def test_readme_example(name, code, armadillo_path, tmp_path, monkeypatch):
    (tmp_path / "cache").symlink_to(SOURCE_DIR / "cache")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, name, "exec"), {"__name__": "__main__"})
    V, F = locus.read_mesh("remeshed.obj")
    assert len(V) >= 500 and F.shape[1] == 3
    assert (tmp_path / "remeshed.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_remesh_script_matches_cli(cli, armadillo_path, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(pathlib_parent(locus.__file__)))
    subprocess.run([sys.executable, str(SOURCE_DIR / "python" / "examples" / "remesh.py"), str(armadillo_path),
                    "--sites", "300", "--iterations", "3", "-o", "py.obj", "--preview", "py.png"],
                   cwd=tmp_path, env=env, check=True, capture_output=True)
    subprocess.run([str(cli), "cvt", str(armadillo_path), "--sites", "300", "--iters", "3", "-o", "cli.obj",
                    "--preview", "cli.png"], cwd=tmp_path, check=True, capture_output=True)
    Vp, Fp = read_obj(tmp_path / "py.obj")
    Vc, Fc = read_obj(tmp_path / "cli.obj")
    assert np.array_equal(Fp, Fc) and np.array_equal(Vp, Vc)
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def pathlib_parent(init_file):
    return os.path.dirname(os.path.dirname(os.path.abspath(init_file)))


def read_obj(path):
    """v/f lines of an OBJ, read here (not by the engine's reader)."""
    V, F = [], []
    for line in path.read_text().splitlines():
        w = line.split()
        if w[:1] == ["v"]:
            V.append([float(x) for x in w[1:4]])
        elif w[:1] == ["f"]:
            F.append([int(x.split("/")[0]) - 1 for x in w[1:]])
    return np.array(V), np.array(F)
