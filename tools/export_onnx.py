#!/usr/bin/env python3
"""Exports an nnshade model blob to ONNX (torch.onnx.export, then onnx.checker), for
engines that import ONNX (Unity Sentis, Unreal NNE). The layouts are fixed; the model's
doc string and metadata repeat them, and docs/weights-format.md states them in full.

    python3 tools/export_onnx.py MODEL.blob OUT.onnx [--output tanh|linear]
            [--bn batch|running] [--height H --width W] [--opset 14]

  nnao.blob  features (N, F) float32, raw per-pixel inputs -> ao (N) in [0, 1]
  G.blob     x (1, C, H, W) float32, H and W multiples of 2^levels -> light (1, 3, H, W):
             Tanh range (--output tanh) or linear light, capped (--output linear)
  D.blob     pair (1, C + 3, H, W): G's input and the light, Tanh range -> logits
H and W are dynamic axes; --height/--width only size the example traced (default: the
smallest multiple of the size step that is at least 64).
"""
import argparse
import os
import sys
import tempfile
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import nnshade_torch as nt  # noqa: E402
from tool_deps import require  # noqa: E402

onnx = require("onnx", "python3-onnx")
torch = nt.torch

GI_CHANNELS = ("0-2 albedo as 2a - 1; 3-5 camera-space normal (x right, y up, z toward the camera); "
               "6 depth 2 min(z / depth_max, 1) - 1, sky 1; 7-9 direct + emission + env light, "
               "mapped 2 L / (L + k) - 1")
COORDS = "; 10-11 CoordConv 2c - 1 of (x, y) in [0, 1] (front mode) or (phi, theta) (surround)"


class LinearLight(torch.nn.Module):
    def __init__(self, g):
        super().__init__()
        self.g = g

    def forward(self, x):
        return self.g.to_linear(self.g(x))


def layout(module, config, output):
    """(model, input name, output name, example input shape, doc string)."""
    if isinstance(module, nt.NnaoNet):
        n = module.fc0.in_features
        doc = (f"features (N, {n}) float32: the raw per-pixel inputs, {config.get('features', 'grid')} layout "
               "(docs/nnao.md, docs/weights-format.md; standardisation is inside the model); "
               "ao (N): ambient occlusion in [0, 1], 1 = unoccluded")
        return module, "features", "ao", (1024, n), doc
    if isinstance(module, nt.Generator):
        c, k = int(config["in_channels"]), module.k
        out = (f"linear light, L = k u / (1 - u), u = (y + 1) / 2 clamped to 1 - 2^-20, capped at light_max "
               f"{module.light_max:g}" if output == "linear" else "Tanh range, L = k u / (1 - u), u = (y + 1) / 2")
        doc = (f"x (1, {c}, H, W) float32, H and W multiples of {module.net.size_multiple}, channels: {GI_CHANNELS}"
               f"{COORDS if c == 12 else ''}; k = hdr_scale = {k:.9g}, depth_max = {float(config['depth_max']):.9g}; "
               f"light (1, 3, H, W) RGB: {out}; BatchNorm uses the batch's statistics unless exported "
               "with --bn running")
        return (LinearLight(module) if output == "linear" else module), "x", "light", None, doc
    c = module.conv0.in_channels
    doc = (f"pair (1, {c}, H, W) float32: the generator's {c - 3} input channels then the light (Tanh range); "
           "logits (1, 1, H', W'): one per patch, no sigmoid")
    return module, "pair", "logits", None, doc


def export(blob, out, output="tanh", bn="batch", height=None, width=None, opset=14):
    kind, config, tensors = nt.read_blob(blob)
    module = nt.from_blob(kind, config, tensors, blob, bn=bn)
    model, name_in, name_out, shape, doc = layout(module, config, output)
    if shape is None:
        step = module.net.size_multiple if isinstance(module, nt.Generator) else 1
        h, w = height or max(step, 64 // step * step), width or max(step, 64 // step * step)
        if h % step or w % step:
            raise ValueError(f"--height {h} and --width {w} must be multiples of {step} for {blob}")
        channels = int(config["in_channels"])
        shape = (1, channels, h, w)
    dynamic = {0: "N"} if len(shape) == 2 else {2: "H", 3: "W"}
    out_dynamic = dict(dynamic) if not isinstance(module, nt.PatchGan) else {2: "H_patches", 3: "W_patches"}
    fd, tmp = tempfile.mkstemp(suffix=".onnx.tmp", dir=os.path.dirname(os.path.abspath(out)))
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp's 0600 is for secrets, not for a model
    # torch 1.13 warns for the empty `roi` input it gives ONNX Resize (Deep Shading's
    # bilinear upsampling); the shapes are right (the checker's full check infers them).
    warnings.filterwarnings("ignore", message="The shape inference of prim::Constant type is missing")
    try:
        with torch.no_grad():
            torch.onnx.export(model, torch.zeros(shape), tmp, input_names=[name_in], output_names=[name_out],
                              dynamic_axes={name_in: dynamic, name_out: out_dynamic}, opset_version=opset)
        m = onnx.load(tmp)
        m.doc_string = doc
        meta = {"nnshade.kind": kind, "nnshade.layout": doc, "nnshade.bn": bn, "nnshade.output": output}
        meta.update({f"nnshade.config.{k}": v for k, v in config.items()})
        for k, v in meta.items():
            m.metadata_props.add(key=k, value=v)
        onnx.checker.check_model(m, full_check=True)
        onnx.save(m, tmp)
        os.replace(tmp, out)  # written whole or not at all
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return doc


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("blob")
    p.add_argument("out")
    p.add_argument("--output", choices=("tanh", "linear"), default="tanh", help="G's output: Tanh range or linear light")
    p.add_argument("--bn", choices=("batch", "running"), default="batch", help="BatchNorm statistics (eval-gi's default: batch)")
    p.add_argument("--height", type=int)
    p.add_argument("--width", type=int)
    p.add_argument("--opset", type=int, default=14)
    a = p.parse_args(argv[1:])
    try:
        doc = export(a.blob, a.out, a.output, a.bn, a.height, a.width, a.opset)
    except (nt.BlobError, ValueError, onnx.checker.ValidationError) as e:
        print(f"export_onnx.py: error: {e}", file=sys.stderr)
        return 1
    print(f"export_onnx.py: wrote {a.out} (onnx.checker passed): {doc}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
