#!/usr/bin/env python3
"""Tests tools/nnshade_torch.py against the C++ forward on the same inputs.

usage: test_nnshade_torch.py PATH_TO_torch_parity_cases
The C++ program (tests/tools/torch_parity_cases.cpp) writes random small models as blobs
and what the C++ computes from them. A torch output t matches the C++ output c when
    |t - c| <= RTOL * (|c| + rms(c))   element-wise, RTOL = 1e-5:
relative to the element, or to the output's typical size for an element near zero
(there the float rounding of terms that cancel is large relative to the element itself).
"""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools"))

import numpy as np  # noqa: E402
import torch  # noqa: E402

import nnao_features_torch as ft  # noqa: E402
import nnshade_torch as nt  # noqa: E402
import read_blob  # noqa: E402
from writer_arg import pop_writer  # noqa: E402

WRITER = None
RTOL = 1e-5
GENERATORS = ["G-pix2pix", "G-pix2pix-mapped", "G-pix2pix-linear", "G-pix2pix-nobn", "G-deepshading", "G-pix2pix-level",
              "G-pix2pix-level-energy"]
DISCRIMINATORS = ["D-patchgan", "D-patchgan-1layer"]
MEASURED = []  # (case, n, max abs difference, max ratio to the tolerance's scale)


def difference(t, c):
    t, c = np.asarray(t, np.float64), np.asarray(c, np.float64)
    d = np.abs(t - c)
    return d.max(), (d / (np.abs(c) + np.sqrt(np.mean(c * c)))).max()


class Cases:
    dir = None

    @staticmethod
    def write():
        Cases.tmp = tempfile.TemporaryDirectory()
        Cases.dir = Cases.tmp.name
        subprocess.run([WRITER, Cases.dir], check=True)

    @staticmethod
    def path(name, what="blob"):
        return os.path.join(Cases.dir, f"{name}.{what}")

    @staticmethod
    def data(name):
        return read_blob.load(Cases.path(name, "cases.blob"))[2]

    @staticmethod
    def run(name, module):
        """(torch outputs, C++ outputs) pairs of a case, one per test mode."""
        c = Cases.data(name)
        with torch.no_grad():
            if name.startswith("nnao"):
                return [(module(torch.from_numpy(c["features"])), c["ao"])]
            x = torch.from_numpy(c["input"])
            key = "tanh_" if name.startswith("G") else "logits_"
            has_bn = any(isinstance(m, nt.BatchNorm2d) for m in module.modules())
            return [(nt.set_modes(module, bn)(x), c[key + bn]) for bn in ("batch", "running")[:1 + has_bn]]


class ParityTest(unittest.TestCase):
    def check(self, name, **modes):
        module = nt.load(Cases.path(name), **modes)
        for i, (t, c) in enumerate(Cases.run(name, module)):
            abs_d, ratio = difference(t, c)
            MEASURED.append((f"{name}{['', ' (running BN)'][i]}", np.size(c), abs_d, ratio))
            self.assertLessEqual(ratio, RTOL, f"{name}: max |torch - C++| = {abs_d:.3g}")
        return module

    def test_nnao_grid_and_horizon(self):
        for name in ("nnao-grid", "nnao-horizon"):
            with self.subTest(name):
                self.check(name)

    def test_generators_in_both_batchnorm_modes(self):
        for name in GENERATORS:
            with self.subTest(name):
                G = self.check(name)
                # The mapping back to linear light (and the light cap), on the C++'s own
                # Tanh output: near Tanh's end it amplifies any difference, so it is
                # checked apart from the network, where it is well conditioned.
                c = Cases.data(name)
                lin = G.to_linear(torch.from_numpy(c["tanh_batch"]))[0]
                abs_d, ratio = difference(lin, c["linear_batch"])
                MEASURED.append((f"{name} to_linear", lin.numel(), abs_d, ratio))
                self.assertLessEqual(ratio, RTOL)

    def test_discriminators_in_both_batchnorm_modes(self):
        for name in DISCRIMINATORS:
            with self.subTest(name):
                self.check(name)

    def test_a_perturbed_weight_or_the_wrong_mode_fails(self):
        # The comparison can fail: noise of 1e-2 on any one parameter tensor is noticed
        # (every tensor is wired in; a single weight may feed a unit that ReLU keeps at
        # 0, and BatchNorm with batch statistics absorbs a scaled one), and so is
        # BatchNorm's other mode.
        gen = torch.Generator().manual_seed(1)
        for name in ["nnao-grid", "nnao-horizon"] + GENERATORS + DISCRIMINATORS:
            module = nt.load(Cases.path(name))
            for pname, p in module.named_parameters():
                with self.subTest(name, parameter=pname), torch.no_grad():
                    saved = p.clone()
                    p += 1e-2 * torch.randn(p.shape, generator=gen)
                    t, c = Cases.run(name, module)[0]
                    p.copy_(saved)
                    self.assertGreater(difference(t, c)[1], RTOL, "a perturbed weight went unnoticed")
        for name in ("G-pix2pix", "D-patchgan"):
            t, _ = Cases.run(name, nt.load(Cases.path(name)))[0]  # batch-statistics output
            _, c = Cases.run(name, nt.load(Cases.path(name)))[1]  # against C++'s running mode
            self.assertGreater(difference(t, c)[1], RTOL)


class NnaoImageTest(unittest.TestCase):
    """tools/nnao_features_torch.py: the inputs, the AO image and the blur from a G-buffer."""

    def gbuffer(self, c, config):
        return ft.GBuffer(torch.from_numpy(c["depth"]), torch.from_numpy(c["normal"]),
                          float(config["fov_y_deg"]), float(config["radius"]))

    def edge_pixels(self, g, window, pixels):
        """Pixels with a grid sample within 1e-4 px of a pixel edge, where float rounding
        (the C++ may contract a multiply-add) can pick either neighbour."""
        edge = torch.zeros(g.h * g.w, dtype=torch.bool)
        for qx, qy in ft.grid_coords(g, window):
            for q in (qx, qy):
                frac = torch.frac(q + 0.5).reshape(-1)
                edge |= (frac < 1e-4) | (frac > 1 - 1e-4)
        return edge[torch.from_numpy(pixels)].numpy()

    def test_inputs_and_image_match_except_on_pixel_edges(self):
        for name in ("nnao-grid", "nnao-horizon"):
            with self.subTest(name):
                config = read_blob.load(Cases.path(name))[1]
                _, cc, c = read_blob.load(Cases.path(name, "cases.blob"))
                g = self.gbuffer(c, cc)
                f = ft.features(config, g).reshape(-1, c["features"].shape[1])[torch.from_numpy(c["pixels"])]
                per_pixel = np.abs(f.numpy() - c["features"]).max(1) / (1 + np.abs(c["features"]).max(1))
                ao = ft.infer_image(nt.load(Cases.path(name)), config, g.z, g.n, float(cc["fov_y_deg"]),
                                    float(cc["radius"]), blur=False)
                edge = (self.edge_pixels(g, int(config["window"]), c["pixels"]) if name == "nnao-grid"
                        else np.zeros(len(per_pixel), bool))
                off = per_pixel > RTOL
                MEASURED.append((f"{name} inputs from the G-buffer", len(per_pixel), per_pixel[~edge].max(),
                                 f"{off.sum()} px off, {edge.sum()} on edges"))
                self.assertFalse((off & ~edge).any(), f"{(off & ~edge).sum()} pixels differ away from pixel edges")
                self.assertLessEqual(off.sum(), 0.05 * len(off))
                ao = ao.reshape(-1)[torch.from_numpy(c["pixels"])].numpy()
                abs_d, ratio = difference(ao[~off], c["ao"][~off])
                MEASURED.append((f"{name} AO image (pixels not off)", int((~off).sum()), abs_d, ratio))
                self.assertLessEqual(ratio, RTOL)

    def test_blur(self):
        _, cc, c = read_blob.load(Cases.path("nnao-horizon", "cases.blob"))
        g = self.gbuffer(c, cc)
        blurred = ft.bilateral_blur(g, torch.from_numpy(c["ao_image"]))
        abs_d, ratio = difference(blurred, c["ao_blurred"])
        MEASURED.append(("bilateral blur", blurred.numel(), abs_d, ratio))
        self.assertLessEqual(ratio, RTOL)
        self.assertGreater(difference(blurred, c["ao_image"])[1], 1e-3)  # it does blur
        loose = ft.bilateral_blur(g, torch.from_numpy(c["ao_image"]), 0.3, 2)
        abs_d, ratio = difference(loose, c["ao_blurred_loose"])
        MEASURED.append(("bilateral blur, depth 0.3, normal power 2", loose.numel(), abs_d, ratio))
        self.assertLessEqual(ratio, RTOL)
        self.assertGreater(difference(loose, blurred)[1], 1e-4)  # the edge terms are in use


class ErrorTest(unittest.TestCase):
    def expect_error(self, what, fn, *args, **kw):
        with self.assertRaises(read_blob.BlobError) as cm:
            fn(*args, **kw)
        self.assertIn(what, str(cm.exception))
        return str(cm.exception)

    def test_a_wrong_kind_is_refused(self):
        p = Cases.path("nnao-grid")
        msg = self.expect_error("holds a 'nnao' model, expected 'pix2pix-unet'", nt.load, p, expected_kind="pix2pix-unet")
        self.assertIn(p, msg)
        self.expect_error("holds a 'pix2pix-unet' model, expected 'patchgan'", nt.load, Cases.path("G-pix2pix"),
                          expected_kind="patchgan")
        self.expect_error("kind 'torch-parity-cases' is not a model this tool builds", nt.load,
                          Cases.path("D-patchgan", "cases.blob"))

    def test_a_missing_file_is_named(self):
        self.expect_error("cannot open '/nonexistent/G.blob'", nt.load, "/nonexistent/G.blob")

    def test_tensors_are_loaded_strictly(self):
        kind, config, tensors = read_blob.load(Cases.path("G-pix2pix"))
        src = Cases.path("G-pix2pix")
        fewer = {k: v for k, v in tensors.items() if k != "G.model.sub.up_norm.running_var"}
        self.expect_error("tensor 'G.model.sub.up_norm.running_var' is missing", nt.from_blob, kind, config, fewer, src)
        extra = dict(tensors, **{"G.model.extra.weight": np.zeros(3, np.float32)})
        self.expect_error("'G.model.extra.weight' does not belong to the model", nt.from_blob, kind, config, extra, src)
        bad = dict(tensors, **{"G.model.down.bias": np.zeros(5, np.float32)})
        self.expect_error("has shape [5], the model expects [4]", nt.from_blob, kind, config, bad, src)
        no_ngf = {k: v for k, v in config.items() if k != "ngf"}
        self.expect_error("config key 'ngf' is missing", nt.from_blob, kind, no_ngf, tensors, src)

    def test_command_line(self):
        tool = os.path.join(ROOT, "tools", "nnshade_torch.py")
        r = subprocess.run([sys.executable, tool, Cases.path("G-deepshading"), Cases.path("nnao-horizon")],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("DeepShadingUnet, residual linear", r.stdout)
        self.assertIn("features (N, 20)", r.stdout)  # 8 directions x 2 bands + 2 + 2
        r = subprocess.run([sys.executable, tool, "/nonexistent/D.blob"], capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("'/nonexistent/D.blob'", r.stderr)

    def test_a_missing_torch_is_explained(self):
        with tempfile.TemporaryDirectory() as fake:
            with open(os.path.join(fake, "torch.py"), "w") as f:
                f.write("raise ImportError(\"No module named 'torch'\")\n")
            r = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "nnshade_torch.py"), Cases.path("G-pix2pix")],
                               capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=fake))
        self.assertEqual(r.returncode, 2)
        self.assertIn(f"the Python module 'torch' is missing for {sys.executable}", r.stderr)
        self.assertIn("python3-torch", r.stderr)
        self.assertNotIn("Traceback", r.stderr)


def report():
    print(f"\n{'case':40s} {'n':>6s} {'max |torch - C++|':>18s} {'max rel':>10s}", file=sys.stderr)
    for case, n, abs_d, rel in MEASURED:
        rel = rel if isinstance(rel, str) else f"{rel:10.3g}"
        print(f"{case:40s} {n:6d} {abs_d:18.3g} {rel:>10s}", file=sys.stderr)


if __name__ == "__main__":
    WRITER = pop_writer(__doc__)
    Cases.write()
    result = unittest.main(exit=False).result
    report()
    Cases.tmp.cleanup()
    sys.exit(0 if result.wasSuccessful() else 1)
