#!/usr/bin/env python3
"""PyTorch modules rebuilt from nnshade's weight blobs, from what docs/weights-format.md
and the model docs state (tests/tools/test_nnshade_torch.py checks them against the C++).

    python3 tools/nnshade_torch.py MODEL.blob...   # what each blob builds, its input and output

    from nnshade_torch import load
    net = load("nnao.blob")                 # NnaoNet: raw per-pixel features (N, F) -> AO (N)
    G = load("G.blob", bn="batch")          # Generator: inputs (1, C, H, W) -> light, Tanh range
    D = load("D.blob", expected_kind="patchgan")  # PatchGan: (1, C+3, H, W) -> logits

Every module is float32 and in eval mode. BatchNorm uses the batch's own statistics
(bn="batch", how eval-gi and gi-infer run G by default) or the stored running ones
(bn="running"); dropout is off unless dropout=True (then masks are torch's, not the C++'s).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from tool_deps import require  # noqa: E402

np = require("numpy", "python3-numpy")
torch = require("torch", "python3-torch")
nn, F = torch.nn, torch.nn.functional

from read_blob import BlobError, for_each_file, load as read_blob  # noqa: E402

BN_EPS = 1e-5          # nn/batchnorm.h, PyTorch's default
MAX_UNIT = 1 - 2**-20  # models/gi/hdr_mapping.h: the inverse mapping's clamp
LINEAR_EPS = 1e-3      # models/gi/generator.h: residual linear, pole moved out of Tanh's range


class Config:
    """A blob's config with errors that name the file (values are strings)."""

    def __init__(self, config, source):
        self.config, self.source = config, source

    def has(self, key):
        return key in self.config

    def str(self, key, default=None):
        if key not in self.config:
            if default is not None:
                return default
            raise BlobError(f"blob '{self.source}': config key '{key}' is missing")
        return self.config[key]

    def num(self, key, cast, default=None):
        v = self.str(key, None if default is None else str(default))
        try:
            return cast(v)
        except ValueError:
            raise BlobError(f"blob '{self.source}': config key '{key}' is '{v}', not {cast.__name__}") from None


class PReLUBeta(nn.Module):
    """NNAO's activation (Holden et al. 2016, eq. 1): beta x for x > 0, alpha x otherwise."""

    def __init__(self, n):
        super().__init__()
        self.alpha, self.beta = nn.Parameter(torch.zeros(n)), nn.Parameter(torch.zeros(n))

    def forward(self, x):
        return torch.where(x > 0, self.beta * x, self.alpha * x)


class NnaoNet(nn.Module):
    """features (N, F) raw, as models/nnao/nnao_inputs.h computes them -> AO (N) in [0, 1]."""

    def __init__(self, features, hidden, horizon_base):
        super().__init__()
        sizes = [features, hidden, hidden, hidden, 1]
        for l in range(4):
            setattr(self, f"fc{l}", nn.Linear(sizes[l], sizes[l + 1]))
            setattr(self, f"act{l}", PReLUBeta(sizes[l + 1]))
        self.register_buffer("feature_mean", torch.zeros(features))
        self.register_buffer("feature_std", torch.ones(features))
        self.register_buffer("target_stats", torch.tensor([0.0, 1.0]))  # mean, std of the target
        self.horizon_base = horizon_base  # feature index the output is added to, or None

    def forward(self, f):
        h = (f - self.feature_mean) / self.feature_std
        for l in range(4):
            h = getattr(self, f"act{l}")(getattr(self, f"fc{l}")(h))
        ao = h[:, 0] * self.target_stats[1] + self.target_stats[0]
        if self.horizon_base is not None:
            ao = ao + f[:, self.horizon_base]
        return ao.clamp(0, 1)


class BatchNorm2d(nn.Module):
    """PyTorch's BatchNorm2d names; batch statistics use the population variance."""

    def __init__(self, c):
        super().__init__()
        self.weight, self.bias = nn.Parameter(torch.ones(c)), nn.Parameter(torch.zeros(c))
        self.register_buffer("running_mean", torch.zeros(c))
        self.register_buffer("running_var", torch.ones(c))
        self.batch_stats = True

    def forward(self, x):
        # Written out rather than F.batch_norm(training=True): it exports to plain ONNX
        # ops, and a test-time module must not move the running statistics.
        if self.batch_stats:
            mean = x.mean(dim=(0, 2, 3), keepdim=True)
            var = ((x - mean) ** 2).mean(dim=(0, 2, 3), keepdim=True)
        else:
            mean, var = self.running_mean.view(1, -1, 1, 1), self.running_var.view(1, -1, 1, 1)
        return (x - mean) * (torch.rsqrt(var + BN_EPS) * self.weight.view(1, -1, 1, 1)) + self.bias.view(1, -1, 1, 1)


def conv4(cin, cout, bias, stride=2):
    return nn.Conv2d(cin, cout, 4, stride, 1, bias=bias)


class UnetBlock(nn.Module):
    """pix2pix's skip block (models/gi/unet.h), level 0 outermost."""

    def __init__(self, c, level):
        super().__init__()
        outermost, innermost = level == 0, level == c["levels"] - 1
        inner = c["ngf"] * min(1 << min(level, 3), 8)
        outer = c["out_channels"] if outermost else c["ngf"] * min(1 << min(level - 1, 3), 8)
        down_bn, up_bn = not outermost and not innermost and c["batchnorm"], not outermost and c["batchnorm"]
        self.level = level
        self.down = conv4(c["in_channels"] if outermost else outer, inner, not down_bn)
        self.down_norm = BatchNorm2d(inner) if down_bn else None
        self.sub = None if innermost else UnetBlock(c, level + 1)
        self.up = nn.ConvTranspose2d(inner if innermost else 2 * inner, outer, 4, 2, 1, bias=not up_bn)
        self.up_norm = BatchNorm2d(outer) if up_bn else None
        with_dropout = not outermost and level >= c["levels"] - c["dropout_blocks"] and c["dropout"] > 0
        self.p = c["dropout"] if with_dropout else 0.0
        self.dropout_on = False

    def forward(self, x):
        h = self.down(x if self.level == 0 else F.leaky_relu(x, 0.2))
        for m in (self.down_norm, self.sub):
            h = h if m is None else m(h)
        h = self.up(F.relu(h))
        h = h if self.up_norm is None else self.up_norm(h)
        if self.p > 0 and self.dropout_on:
            h = F.dropout(h, self.p, training=True)  # inverted: kept values scaled by 1/(1-p)
        return torch.tanh(h) if self.level == 0 else torch.cat([x, h], 1)


class Pix2PixUnet(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.model = UnetBlock(c, 0)
        self.size_multiple = 1 << c["levels"]
        if c["level_head"] > 0:  # models/gi/unet.h: UnetGenerator::level_gain
            self.level_energy = c["level_energy"]
            nf = 2 * c["in_channels"] + (6 if self.level_energy else 0)
            self.level_head_in = nn.Linear(nf, c["level_head"])
            self.level_head_out = nn.Linear(c["level_head"], c["out_channels"])

    def forward(self, x):
        return self.model(x)

    def level_gain(self, x):
        """Per-frame gains (B, 3, 1, 1) of the indirect light from the input's channel means
        and mean squares over the whole view, and with the energy the log mean linear
        lumination and albedo x lumination per colour (models/gi/frame_level_features.h);
        None without the head."""
        if not hasattr(self, "level_head_in"):
            return None
        f = [x.mean((2, 3)), (x * x).mean((2, 3))]
        if self.level_energy:
            xd = x.double()
            a = 0.5 * (xd[:, 0:3] + 1)
            u = (0.5 * (xd[:, 7:10] + 1)).clamp(0, 1 - 2.0**-20)
            light = u / (1 - u)
            f += [torch.log(light.mean((2, 3)) + 1e-3).to(x.dtype), torch.log((a * light).mean((2, 3)) + 1e-3).to(x.dtype)]
        f = torch.cat(f, 1)
        h = F.leaky_relu(self.level_head_in(f), 0.2)
        return torch.exp(self.level_head_out(h)).view(x.shape[0], -1, 1, 1)


class DeepShadingUnet(nn.Module):
    """Deep Shading's U-Net (models/gi/deep_shading_unet.h): 3x3 convs with bias, leaky 0.01."""

    def __init__(self, c):
        super().__init__()
        L, u0, k = c["levels"] + 1, c["ngf"], 3
        width = [u0 << l for l in range(L)]
        self.levels, self.size_multiple = L, 1 << (L - 1)
        for l in range(L):
            setattr(self, f"down{l}", nn.Conv2d(c["in_channels"] if l == 0 else width[l - 1], width[l], k, 1, k // 2))
        for l in range(max(L - 1, 1)):
            cin = width[l] + (width[l + 1] if L > 1 else 0)
            setattr(self, f"up{l}", nn.Conv2d(cin, c["out_channels"] if l == 0 else width[l], k, 1, k // 2))

    def forward(self, x):
        skips, h = [], x
        for l in range(self.levels):
            h = F.leaky_relu(getattr(self, f"down{l}")(h if l == 0 else F.avg_pool2d(h, 2)), 0.01)
            skips.append(h)
        for l in range(self.levels - 2, -1, -1):
            up = F.interpolate(h, scale_factor=2, mode="bilinear", align_corners=False)
            h = getattr(self, f"up{l}")(torch.cat([up, skips[l]], 1))
            h = torch.tanh(h) if l == 0 else F.leaky_relu(h, 0.01)
        return torch.tanh(self.up0(h)) if self.levels == 1 else h


class Generator(nn.Module):
    """G.blob: the network plus its residual mode (models/gi/generator.h). Input (1, C, H, W)
    as models/gi/gi_inputs.h assembles it; output the light of every pixel, Tanh range."""

    def __init__(self, net, residual, hdr_scale, light_max):
        super().__init__()
        self.net, self.residual, self.k, self.light_max = net, residual, hdr_scale, light_max

    def forward(self, x):
        y = self.net(x)
        if self.residual == "off":
            return y
        lum = x[:, 7:10]  # direct + emission + env, HDR-mapped
        if self.residual == "mapped":
            return y * 2 + lum
        k, eps = self.k, LINEAR_EPS
        u = (0.5 * (lum + 1)).clamp(0, 1 - eps)
        indirect = (y * (0.5 * k) + 0.5 * k) / (y * -0.5 + (0.5 + eps))
        gain = self.net.level_gain(x) if hasattr(self.net, "level_gain") else None
        if gain is not None:
            indirect = indirect * gain
        return (k / (indirect + k * u / (1 - u) + k)) * -2 + 1

    def to_linear(self, y):
        """Tanh range -> linear light, capped at light_max (predict_linear in gi_model_io.h)."""
        u = (0.5 * (y + 1)).clamp(0, MAX_UNIT)
        return (self.k * u / (1 - u)).clamp(0, self.light_max)  # both bounds: ONNX Clip wants two


class PatchGan(nn.Module):
    """pix2pix's NLayerDiscriminator (models/gi/patchgan.h): logits, no sigmoid."""

    def __init__(self, cin, ndf, layers):
        super().__init__()
        self.n, ch = layers, cin
        for n in range(layers + 1):
            out = ndf * min(1 << min(n, 3), 8)
            setattr(self, f"conv{n}", conv4(ch, out, n == 0, 2 if n < layers else 1))
            setattr(self, f"norm{n}", BatchNorm2d(out) if n > 0 else None)
            ch = out
        self.head = conv4(ch, 1, True, 1)

    def forward(self, x):
        for n in range(self.n + 1):
            x, norm = getattr(self, f"conv{n}")(x), getattr(self, f"norm{n}")
            x = F.leaky_relu(x if norm is None else norm(x), 0.2)
        return self.head(x)


def build_nnao(c):
    kind = c.str("features", "grid")
    if kind == "grid":
        nfeat, base = 4 * c.num("window", int) ** 2, None
    elif kind == "horizon":
        d, b = c.num("directions", int), c.num("bands", int)
        nfeat = d * b + 2 + b
        base = nfeat - 1  # the last band's visibility: the target is AO minus it
    else:
        raise BlobError(f"blob '{c.source}': features must be 'grid' or 'horizon', not '{kind}'")
    return NnaoNet(nfeat, c.num("hidden", int), base), ""


def build_generator(c):
    g = {k: c.num(k, int) for k in ("in_channels", "out_channels", "ngf", "levels", "dropout_blocks")}
    g["dropout"], g["batchnorm"] = c.num("dropout", float), c.str("batchnorm", "on") != "off"
    g["level_head"] = c.num("level_head", int, 0)
    g["level_energy"] = c.str("level_energy", "off") == "on"
    arch, residual = c.str("arch", "pix2pix"), c.str("residual", "off")
    residual = {"on": "mapped"}.get(residual, residual)  # the name blobs of early runs carry
    if arch not in ("pix2pix", "deepshading") or residual not in ("off", "mapped", "linear"):
        raise BlobError(f"blob '{c.source}': unknown arch '{arch}' or residual '{residual}'")
    net = Pix2PixUnet(g) if arch == "pix2pix" else DeepShadingUnet(g)
    return Generator(net, residual, c.num("hdr_scale", float), c.num("light_max", float, float("inf"))), "G."


def build_discriminator(c):
    return PatchGan(c.num("in_channels", int), c.num("ndf", int), c.num("layers", int)), "D."


BUILDERS = {"nnao": build_nnao, "pix2pix-unet": build_generator, "patchgan": build_discriminator}


def load_tensors(module, tensors, prefix, source):
    """Strict, like nn/serialize.h: every float tensor of the blob fills a parameter or
    buffer of the same name and shape, and every one is filled. Dropout generator states
    (u64 '.rng') are skipped: torch draws its own masks."""
    target = module.net if isinstance(module, Generator) else module
    own, seen = target.state_dict(), set()
    for name, a in tensors.items():
        key = name[len(prefix):] if name.startswith(prefix) else None
        if a.dtype == np.uint64 and name.endswith(".rng"):
            continue
        if key not in own:
            raise BlobError(f"blob '{source}': tensor '{name}' does not belong to the model (unexpected name)")
        if tuple(a.shape) != tuple(own[key].shape):
            raise BlobError(f"blob '{source}': tensor '{name}' has shape {list(a.shape)}, "
                            f"the model expects {list(own[key].shape)}")
        own[key].copy_(torch.from_numpy(a.astype(np.float32)))
        seen.add(key)
    missing = [prefix + k for k in own if k not in seen]
    if missing:
        raise BlobError(f"blob '{source}': tensor '{missing[0]}' is missing ({len(missing)} in all)")


def set_modes(module, bn="batch", dropout=False):
    if bn not in ("batch", "running"):
        raise ValueError(f"bn must be 'batch' or 'running', not '{bn}'")
    for m in module.modules():
        if isinstance(m, BatchNorm2d):
            m.batch_stats = bn == "batch"
        if isinstance(m, UnetBlock):
            m.dropout_on = dropout
    return module.eval()


def from_blob(kind, config, tensors, source, expected_kind=None, bn="batch", dropout=False):
    if expected_kind is not None and kind != expected_kind:
        raise BlobError(f"blob '{source}': holds a '{kind}' model, expected '{expected_kind}'")
    if kind not in BUILDERS:
        hint = " (a train-gan run folder has G.blob and D.blob beside it)" if "checkpoint" in kind else ""
        raise BlobError(f"blob '{source}': kind '{kind}' is not a model this tool builds "
                        f"({', '.join(BUILDERS)}){hint}")
    module, prefix = BUILDERS[kind](Config(config, source))
    load_tensors(module, tensors, prefix, source)
    return set_modes(module, bn, dropout)


def load(path, expected_kind=None, bn="batch", dropout=False):
    """The torch module of the blob at `path` (BlobError naming the file if it cannot)."""
    kind, config, tensors = read_blob(path)
    return from_blob(kind, config, tensors, path, expected_kind, bn, dropout)


def describe(module):
    params = sum(p.numel() for p in module.parameters())
    if isinstance(module, NnaoNet):
        kind = "horizon" if module.horizon_base is not None else "grid"
        what = (f"NnaoNet ({kind} features): features (N, {module.fc0.in_features}) float32, raw "
                "(docs/weights-format.md) -> AO (N) in [0, 1]")
    elif isinstance(module, Generator):
        m, cin = module.net.size_multiple, (module.net.model.down if isinstance(module.net, Pix2PixUnet)
                                            else module.net.down0).in_channels
        what = (f"Generator ({type(module.net).__name__}, residual {module.residual}, k = {module.k:g}): "
                f"x (1, {cin}, H, W), H and W multiples of {m} (docs/weights-format.md) -> light (1, 3, H, W), Tanh range")
    else:
        what = f"PatchGan: (1, {module.conv0.in_channels}, H, W) -> logits (1, 1, H', W')"
    return f"{what}; {params} parameters"


def main(argv):
    return for_each_file(argv, __doc__, lambda path: f"{path}: {describe(load(path))}")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
