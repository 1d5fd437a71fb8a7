"""NNAO's per-pixel inputs and its blur in PyTorch, from a G-buffer, as
docs/weights-format.md ("The models in the blobs") states them: with nnshade_torch's
NnaoNet this is nnao-infer's exact inference, image in, AO image out.

    from nnao_features_torch import infer_image
    ao = infer_image(net, config, depth, normal, fov_y_deg, radius)   # (H, W)

depth (H, W) planar, sky +inf (or >= 1e30); normal (3, H, W) camera space; float32.
The math is the C++'s, in float32, operation for operation where it matters; a sample
that lands within rounding of a pixel edge may still pick the neighbouring pixel
(tests/tools/test_nnshade_torch.py counts such pixels).
"""
import math

import nnshade_torch as nt

torch = nt.torch


class GBuffer:
    def __init__(self, depth, normal, fov_y_deg, radius):
        self.z, self.n = depth.float(), normal.float()
        self.h, self.w = depth.shape
        f32 = lambda v: torch.tensor(v, dtype=torch.float32)  # noqa: E731 (float math, as the C++)
        self.sy = torch.tan(f32(fov_y_deg) * f32(3.14159265358979) / 360)
        self.sx = self.sy * self.w / self.h
        self.r = torch.tensor(radius, dtype=torch.float32)
        self.sky = ~(self.z < 1e30) | (self.z <= 0)
        py, px = torch.meshgrid(torch.arange(self.h, dtype=torch.float32),
                                torch.arange(self.w, dtype=torch.float32), indexing="ij")
        self.px, self.py = px, py
        self.P = self.position(px, py, self.z)

    def position(self, px, py, z):
        return torch.stack([((px + 0.5) * (2 / self.w) - 1) * self.sx * z,
                            (1 - (py + 0.5) * (2 / self.h)) * self.sy * z, -z])

    def nearest(self, qx, qy):
        """Flat index of the nearest pixel, clamped to the screen (rounds half up). Sky
        centres (infinite depth) give NaN coordinates: any pixel will do, their result is 1."""
        ix = torch.floor(torch.nan_to_num(qx) + 0.5).clamp(0, self.w - 1).long()
        iy = torch.floor(torch.nan_to_num(qy) + 0.5).clamp(0, self.h - 1).long()
        return iy * self.w + ix

    def at(self, plane, index):
        return plane.reshape(plane.shape[0], -1)[:, index] if plane.dim() == 3 else plane.reshape(-1)[index]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def grid_coords(g, window):
    """The continuous pixel coordinates (qx, qy) of every grid sample, in feature order:
    column i left to right, row j top to bottom."""
    z, P, r = g.z, g.P, g.r
    kx, ky = 0.5 * g.w / (g.sx * z), 0.5 * g.h / (g.sy * z)
    cx = (P[0] / (g.sx * z) + 1) * 0.5 * g.w - 0.5  # the centre projected back, as the C++ does
    cy = (1 - P[1] / (g.sy * z)) * 0.5 * g.h - 0.5
    step = 2 * r / (window - 1) if window > 1 else r * 0
    return [(cx + (i * step - r) * kx, cy + (j * step - r) * ky) for j in range(window) for i in range(window)]


def grid_features(g, window):
    """(H, W, 4 w^2), 4 values per sample."""
    z, P, N, r = g.z, g.P, g.n, g.r
    out = []
    for qx, qy in grid_coords(g, window):
        s = g.nearest(qx, qy)
        D = g.at(g.P, s) - P
        d2 = dot(D, D) * ((1 / r) * (1 / r))
        near = ~g.at(g.sky, s) & (d2 < 1)  # else all four are 0 (a sky sample's depth is inf)
        fall = 1 - torch.sqrt(d2)
        values = [fall * (g.at(g.n, s)[c] - N[c]) for c in range(3)] + [fall * (g.at(g.z, s) - z) * (1 / r)]
        out += [torch.where(near, v, torch.zeros_like(v)) for v in values]
    return torch.stack(out, -1)


def horizon_features(g, directions, steps, bands, radius_term_max=0.0):
    """(H, W, D B + 2 + B): horizons per direction and band, N.V, radius term, visibilities.
    radius_term_max: the blob's ceiling on the radius term (0: none)."""
    length = torch.sqrt(dot(g.n, g.n))
    N = torch.where(length > 0, (1 / length) * g.n, torch.tensor([0.0, 0.0, 1.0]).view(3, 1, 1))
    P, r2 = g.P, g.r * g.r
    R = g.r * 0.5 * g.w / (g.sx * g.z)
    sxn, syn = N[0], -N[1]
    sl = torch.sqrt(sxn * sxn + syn * syn)
    c0 = torch.where(sl > 1e-4, sxn / sl, torch.ones_like(sl))
    s0 = torch.where(sl > 1e-4, syn / sl, torch.zeros_like(sl))
    per_band, feats = steps // bands, []
    for k in range(directions):
        a = torch.tensor(6.2831853, dtype=torch.float32) * k / directions
        ox, oy = c0 * torch.cos(a) - s0 * torch.sin(a), s0 * torch.cos(a) + c0 * torch.sin(a)
        h, on = torch.zeros_like(g.z), torch.ones_like(g.sky)
        for s in range(steps):
            f = (s + 0.5) / steps
            t = 1 + f * f * R
            qx, qy = g.px + ox * t, g.py + oy * t
            on = on & (qx > -0.5) & (qy > -0.5) & (qx < g.w - 0.5) & (qy < g.h - 0.5)  # a march stops
            j = g.nearest(qx, qy)
            d = g.at(P, j) - P
            d2 = dot(d, d)
            ok = on & ~g.at(g.sky, j) & (d2 > 0) & (d2 <= r2)
            h = torch.where(ok, torch.maximum(h, dot(N, d) / torch.sqrt(d2)), h)
            if (s + 1) % per_band == 0:
                feats.append(h)
    hz = torch.stack(feats, -1)  # (H, W, D B), direction-major
    V = (1 / torch.sqrt(dot(P, P))) * -P
    vis = [1 - (hz[..., b::bands] ** 2).sum(-1) / directions for b in range(bands)]
    radius_term = torch.clamp(torch.log2(1 + R) / 8, max=radius_term_max) if radius_term_max else torch.log2(1 + R) / 8
    return torch.cat([hz, torch.stack([dot(N, V), radius_term] + vis, -1)], -1)


def pow_by_squaring(x, p):
    """x^p multiplied in the order of nnao_weights.h's pow_by_squaring (same bits)."""
    r = torch.ones_like(x)
    while p > 0:
        if p & 1:
            r = r * x
        if p > 1:
            x = x * x
        p >>= 1
    return r


def bilateral_blur(g, ao, depth=0.1, normal_power=8):
    """The 5x5 separable depth- and normal-aware blur after a horizon model; sky stays 1.
    depth, normal_power: the edge terms (the blob's blur_depth, blur_normal_power)."""
    spatial = [math.exp(-k * k / (2 * 1.5 * 1.5)) for k in range(-2, 3)]
    inv_dz = 1 / (torch.tensor(depth, dtype=torch.float32) * g.r)
    for dx, dy in ((1, 0), (0, 1)):
        s, ws = torch.zeros_like(ao), torch.zeros_like(ao)
        for k in range(-2, 3):
            qx, qy = g.px + k * dx, g.py + k * dy
            inside = (qx >= 0) & (qy >= 0) & (qx < g.w) & (qy < g.h)
            j = g.nearest(qx, qy)
            dz = (g.at(g.z, j) - g.z) * inv_dz
            nd = pow_by_squaring(torch.clamp(dot(g.n, g.at(g.n, j)), min=0), normal_power)
            w = torch.where(inside & ~g.at(g.sky, j), spatial[k + 2] * torch.exp(-dz * dz) * nd, torch.zeros_like(dz))
            s, ws = s + w * g.at(ao, j), ws + w
        ao = torch.where(g.sky, torch.ones_like(ao), torch.where(ws > 0, s / ws, ao))
    return ao


def features(config, g):
    if config.get("features", "grid") == "horizon":
        return horizon_features(g, int(config["directions"]), int(config["steps"]), int(config["bands"]),
                                float(config.get("radius_term_max", 0)))
    return grid_features(g, int(config["window"]))


def infer_image(net, config, depth, normal, fov_y_deg, radius, blur=None):
    """nnao-infer's exact AO image: the network on every non-sky pixel's inputs, 1 on sky,
    then the blur for a horizon model (blur=None: the blob's blur_passes times) or once as asked."""
    g = GBuffer(depth, normal, fov_y_deg, radius)
    f = features(config, g)
    with torch.no_grad():
        ao = net(f.reshape(-1, f.shape[-1])).reshape(g.h, g.w)
    ao = torch.where(g.sky, torch.ones_like(ao), ao)
    if blur if blur is not None else config.get("features") == "horizon":
        edges = (float(config.get("blur_depth", 0.1)), int(config.get("blur_normal_power", 8)))
        for _ in range(int(config.get("blur_passes", 1)) if blur is None else 1):
            ao = bilateral_blur(g, ao, *edges)
    return ao
