#!/usr/bin/env python3
"""Tests tools/export_onnx.py: random small models (written by the C++,
tests/tools/torch_parity_cases.cpp) exported to ONNX pass onnx.checker, with the
documented input and output layouts, and carry the blob's weights. Debian 12 has no
ONNX runtime, so the exported graph is not run here; the torch modules it is traced
from are checked against the C++ by test_nnshade_torch.py.

usage: test_export_onnx.py PATH_TO_torch_parity_cases
"""
import contextlib
import io
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
TOOL = os.path.join(ROOT, "tools", "export_onnx.py")
sys.path.insert(0, os.path.join(ROOT, "tools"))

import numpy as np  # noqa: E402
import onnx  # noqa: E402
from onnx import numpy_helper  # noqa: E402

import export_onnx  # noqa: E402
import read_blob  # noqa: E402
from writer_arg import pop_writer  # noqa: E402

WRITER = None

# case, extra flags, input (name, shape), output (name, shape); strings are dynamic axes.
EXPORTS = [
    ("nnao-grid", [], ("features", ["N", 100]), ("ao", ["N"])),
    ("nnao-horizon", [], ("features", ["N", 20]), ("ao", ["N"])),
    ("G-pix2pix", [], ("x", [1, 12, "H", "W"]), ("light", [1, 3, "H", "W"])),
    ("G-pix2pix-mapped", ["--bn", "running", "--height", "32", "--width", "48"], ("x", [1, 10, "H", "W"]),
     ("light", [1, 3, "H", "W"])),
    ("G-pix2pix-level-energy", ["--output", "linear"], ("x", [1, 12, "H", "W"]), ("light", [1, 3, "H", "W"])),
    ("G-deepshading", ["--output", "linear"], ("x", [1, 12, "H", "W"]), ("light", [1, 3, "H", "W"])),
    ("D-patchgan", [], ("pair", [1, 15, "H", "W"]), ("logits", [1, 1, "H_patches", "W_patches"])),
]


def dims(value_info):
    return [d.dim_param or d.dim_value for d in value_info.type.tensor_type.shape.dim]


def export(*args):
    """The tool in this process (importing torch once), as its command line runs it."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = export_onnx.main(["export_onnx.py", *args])
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


class ExportOnnxTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = cls.tmp.name
        subprocess.run([WRITER, cls.dir], check=True)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def blob(self, name):
        return os.path.join(self.dir, name + ".blob")

    def test_exports_pass_the_checker_with_the_documented_layout(self):
        for name, flags, (in_name, in_dims), (out_name, out_dims) in EXPORTS:
            with self.subTest(name):
                out = os.path.join(self.dir, name + ".onnx")
                r = export(self.blob(name), out, *flags)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn("onnx.checker passed", r.stdout)
                self.assertNotIn("Warning", r.stderr)
                m = onnx.load(out)
                onnx.checker.check_model(m, full_check=True)  # again, apart from the tool
                self.assertEqual(m.opset_import[0].version, 14)
                self.assertEqual([(i.name, dims(i)) for i in m.graph.input], [(in_name, in_dims)])
                self.assertEqual([(o.name, dims(o)) for o in m.graph.output], [(out_name, out_dims)])
                self.assertEqual(m.graph.input[0].type.tensor_type.elem_type, onnx.TensorProto.FLOAT)
                meta = {p.key: p.value for p in m.metadata_props}
                kind, config, tensors = read_blob.load(self.blob(name))
                self.assertEqual(meta["nnshade.kind"], kind)
                self.assertEqual(meta["nnshade.layout"], m.doc_string)
                self.assertTrue(all(meta[f"nnshade.config.{k}"] == v for k, v in config.items()))
                # Every weight matrix and kernel of the blob is in the graph, unchanged.
                inits = [numpy_helper.to_array(i) for i in m.graph.initializer]
                for tname, w in tensors.items():
                    if w.ndim >= 2:
                        self.assertTrue(any(i.shape == w.shape and np.array_equal(i, w) for i in inits), tname)

    def test_the_layout_states_the_hdr_mapping_and_channels(self):
        out = os.path.join(self.dir, "layout.onnx")
        self.assertEqual(export(self.blob("G-pix2pix"), out, "--output", "linear").returncode, 0)
        doc = onnx.load(out).doc_string
        for what in ("0-2 albedo as 2a - 1", "6 depth 2 min(z / depth_max, 1) - 1", "mapped 2 L / (L + k) - 1",
                     "10-11 CoordConv", "k = hdr_scale = 0.600000024", "capped at light_max 3",
                     "multiples of 8"):
            self.assertIn(what, doc)

    def test_errors_name_the_file_and_leave_nothing_behind(self):
        out = os.path.join(self.dir, "bad.onnx")
        for args, what in [((os.path.join(self.dir, "none.blob"), out), "cannot open"),
                           ((os.path.join(self.dir, "G-pix2pix.cases.blob"), out), "is not a model this tool builds"),
                           ((self.blob("G-pix2pix"), out, "--height", "20"), "multiples of 8")]:
            with self.subTest(what):
                r = export(*args)
                self.assertEqual(r.returncode, 1, r.stderr)
                self.assertIn(what, r.stderr)
                self.assertIn(args[0], r.stderr)
                self.assertFalse(os.path.exists(out))
        self.assertEqual([f for f in os.listdir(self.dir) if f.endswith(".tmp")], [])

    def test_command_line(self):
        out = os.path.join(self.dir, "cli.onnx")
        r = subprocess.run([sys.executable, TOOL, self.blob("nnao-grid"), out], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        onnx.checker.check_model(onnx.load(out))
        r = subprocess.run([sys.executable, TOOL, self.blob("none"), out], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn(f"export_onnx.py: error: cannot open '{self.blob('none')}'", r.stderr)


if __name__ == "__main__":
    WRITER = pop_writer(__doc__)
    unittest.main()
