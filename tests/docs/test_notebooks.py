"""The example notebooks of docs/notebooks/ run from a fresh kernel without an error (nbclient),
so that they stay true: each asserts its numbers against a published or independent value
(paper 001's R2 and R3 as linkwork derives them, the sine press's stroke 2 L1 / sin alpha, the
swash plate's 2 R tan alpha, the closed-form four-bar against the engine, Kennedy's theorem,
the friction example of docs/friction.md) and displays the studies (their ``_repr_html_``)."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "docs" / "notebooks").glob("*.ipynb"))
#: The topics that have a page in docs/ and a notebook.
TOPICS = {"balancing", "fourbar", "friction", "planar", "redundancy", "sine_press",
          "swashplate"}


def test_one_notebook_per_topic():
    assert {p.stem for p in NOTEBOOKS} == TOPICS
    assert all((ROOT / "docs" / f"{t}.md").is_file() for t in TOPICS)


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, kernel_name="python3", timeout=600,
                                     resources={"metadata": {"path": str(ROOT)}})
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    html = [o for o in outputs if "text/html" in o.get("data", {})]
    assert any("lw-root" in o["data"]["text/html"] for o in html)   # a linkwork display
