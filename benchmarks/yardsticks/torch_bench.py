#!/usr/bin/python3
"""PyTorch CPU yardsticks for benchmarks/compare: the same work as nnshade's benchmarks.

    torch_bench.py KEY --threads N --reps R --min-seconds S [--shapes M,N,K,TA,TB ...]

Prints one JSON object per measured row and line:
    {"key": shape or configuration, "threads": N, "seconds": [mean time of one call, per repetition],
     "flops": work per call or null, "peak_rss_mib": ..., "import_rss_mib": ...}
(peak RSS of this process so far, and its RSS once Python and torch were imported).
Run by benchmarks/compare (which also picks the allocator environment); never by CMake.
Keys: sgemm, conv, convT, batchnorm, nnao_step, gan_iteration.
--bf16 (sgemm, conv, convT, gan_iteration): sgemm multiplies bf16 tensors (torch.mm in
bf16, oneDNN's bf16 matmul); the others run their forward passes under
torch.autocast("cpu", dtype=torch.bfloat16), PyTorch's mixed precision. Rows then carry
"isa": what PyTorch reports for its CPU kernels and oneDNN's bf16 support.
"""
import argparse
import json
import resource
import sys
import time

import torch
import torch.nn as nn
import torch.nn.functional as F
from contextlib import nullcontext

ARGS = None  # the parsed arguments (emit and the conv helpers read --bf16)

# Part of every peak below, but the runtime's rather than the workload's.
IMPORT_RSS_MIB = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def timed(fn, reps, min_seconds):
    """Mean seconds per call in each repetition (each repeats fn for >= min_seconds)."""
    fn()  # warm-up: allocations, oneDNN primitive creation
    out = []
    for _ in range(reps):
        calls, t0 = 0, time.perf_counter()
        while True:
            fn()
            calls += 1
            elapsed = time.perf_counter() - t0
            if elapsed >= min_seconds:
                break
        out.append(elapsed / calls)
    return out


def peak_rss_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def cpu_isa():
    """The implementations oneDNN picks for a bf16 matmul and an autocast convolution,
    from oneDNN's verbose log of a small probe in a child process (its log goes to the
    C stdout, which this process cannot read back)."""
    global CPU_ISA
    if CPU_ISA is None:
        import os
        import subprocess
        probe = ("import torch\na = torch.rand(64, 64).bfloat16(); torch.mm(a, a)\n"
                 "c = torch.nn.Conv2d(8, 8, 3)\n"
                 "with torch.autocast('cpu', dtype=torch.bfloat16): c(torch.rand(1, 8, 16, 16))\n")
        env = dict(os.environ, ONEDNN_VERBOSE="1", DNNL_VERBOSE="1")
        out = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True, text=True).stdout
        impl = {}
        for line in out.splitlines():
            f = line.split(",")
            if len(f) > 4 and f[1] == "exec" and f[3] in ("matmul", "convolution"):
                impl.setdefault(f[3], f[4])
        CPU_ISA = "oneDNN " + ", ".join(f"{k} {v}" for k, v in impl.items()) if impl else "oneDNN: no log"
    return CPU_ISA


CPU_ISA = None


def autocast(args):
    return torch.autocast("cpu", dtype=torch.bfloat16) if args.bf16 else nullcontext()


def emit(key, threads, seconds, flops=None, **extra):
    row = {"key": key, "threads": threads, "seconds": seconds, "flops": flops,
           "peak_rss_mib": peak_rss_mib(), "import_rss_mib": IMPORT_RSS_MIB}
    row.update(extra)
    if ARGS.bf16:
        row["isa"] = cpu_isa()
    print(json.dumps(row), flush=True)


# ---- SGEMM -------------------------------------------------------------------------
def bench_sgemm(args):
    for s in args.shapes:
        M, N, K, ta, tb = (int(x) for x in s.split(","))
        A = torch.rand(K, M) if ta else torch.rand(M, K)
        B = torch.rand(N, K) if tb else torch.rand(K, N)
        if args.bf16:
            A, B = A.bfloat16(), B.bfloat16()
        A = A.t() if ta else A  # a transposed view, as BLAS sees it
        B = B.t() if tb else B
        C = torch.empty(M, N, dtype=A.dtype)
        sec = timed(lambda: torch.mm(A, B, out=C), args.reps, args.min_seconds)
        emit(s, args.threads, sec, 2.0 * M * N * K)


# ---- convolutions (shapes Cin,Cout,k,stride,pad,HW for an input 1 x Cin x HW x HW) -----
def fwd_bwd(module, x):
    with torch.no_grad(), autocast(ARGS):
        grad_out = torch.randn_like(module(x))

    def step():
        module.zero_grad(set_to_none=False)
        x.grad = None
        with autocast(ARGS):
            y = module(x)
        y.backward(grad_out)
    return step


def fwd_only(module, x):
    def step():
        with torch.no_grad(), autocast(ARGS):
            module(x)
    return step


def bench_conv(args, transposed):
    for s in args.shapes:
        cin, cout, k, stride, pad, hw = (int(v) for v in s.split(","))
        layer = (nn.ConvTranspose2d if transposed else nn.Conv2d)(cin, cout, k, stride, pad, bias=True)
        x = torch.randn(1, cin, hw, hw, requires_grad=args.pass_ == "fwdbwd")
        out_hw = layer(x).shape[-1] ** 2
        # A transposed conv has the MACs of the convolution it inverts (output -> input).
        macs = cout * hw * hw * cin * k * k if transposed else cout * out_hw * cin * k * k
        flops = 2.0 * macs * (3 if args.pass_ == "fwdbwd" else 1)
        fn = fwd_bwd(layer, x) if args.pass_ == "fwdbwd" else fwd_only(layer, x)
        emit(s, args.threads, timed(fn, args.reps, args.min_seconds), flops)


# ---- batchnorm (shapes N,C,HW for N x C x HW x HW, train mode, forward + backward) -------
def bench_batchnorm(args):
    for s in args.shapes:
        n, c, hw = (int(v) for v in s.split(","))
        bn = nn.BatchNorm2d(c).train()
        x = torch.randn(n, c, hw, hw, requires_grad=True)
        emit(s, args.threads, timed(fwd_bwd(bn, x), args.reps, args.min_seconds), None)


# ---- NNAO MLP training step -------------------------------------------------------------
class PReLUBeta(nn.Module):
    """NNAO eq. 1: f(x) = beta * max(x, 0) + alpha * min(x, 0), per unit."""

    def __init__(self, units):
        super().__init__()
        self.alpha = nn.Parameter(torch.full((units,), 0.25))
        self.beta = nn.Parameter(torch.ones(units))

    def forward(self, x):
        return self.beta * torch.clamp(x, min=0) + self.alpha * torch.clamp(x, max=0)


def bench_nnao_step(args):
    torch.manual_seed(0)
    sizes = [args.window * args.window * 4, 4, 4, 4, 1]
    layers = [nn.Dropout(0.5)]
    for i in range(len(sizes) - 1):
        layers.append(nn.Linear(sizes[i], sizes[i + 1]))
        if i < len(sizes) - 2:
            layers.append(PReLUBeta(sizes[i + 1]))
    model = nn.Sequential(*layers).train()
    opt = torch.optim.Adam(model.parameters(), lr=1e-3)
    x, y = torch.rand(args.batch, sizes[0]), torch.rand(args.batch, 1)

    def step():
        opt.zero_grad(set_to_none=False)
        F.mse_loss(model(x), y).backward()
        opt.step()
    sec = timed(step, args.reps, args.min_seconds)
    emit(f"{args.window},{args.batch}", args.threads, sec, None,
         samples_per_s=[args.batch / s for s in sec])


# ---- pix2pix iteration (networks.py layout) ---------------------------------------------
class UnetSkipConnectionBlock(nn.Module):
    def __init__(self, outer_nc, inner_nc, input_nc=None, submodule=None, outermost=False,
                 innermost=False, use_dropout=False):
        super().__init__()
        self.outermost = outermost
        use_bias = False  # BatchNorm has its own affine shift
        input_nc = outer_nc if input_nc is None else input_nc
        downconv = nn.Conv2d(input_nc, inner_nc, 4, 2, 1, bias=use_bias)
        downrelu, downnorm = nn.LeakyReLU(0.2, True), nn.BatchNorm2d(inner_nc)
        uprelu, upnorm = nn.ReLU(True), nn.BatchNorm2d(outer_nc)
        if outermost:
            upconv = nn.ConvTranspose2d(inner_nc * 2, outer_nc, 4, 2, 1)
            model = [downconv, submodule, uprelu, upconv, nn.Tanh()]
        elif innermost:
            upconv = nn.ConvTranspose2d(inner_nc, outer_nc, 4, 2, 1, bias=use_bias)
            model = [downrelu, downconv, uprelu, upconv, upnorm]
        else:
            upconv = nn.ConvTranspose2d(inner_nc * 2, outer_nc, 4, 2, 1, bias=use_bias)
            model = [downrelu, downconv, downnorm, submodule, uprelu, upconv, upnorm]
            if use_dropout:
                model.append(nn.Dropout(0.5))
        self.model = nn.Sequential(*model)

    def forward(self, x):
        return self.model(x) if self.outermost else torch.cat([x, self.model(x)], 1)


def unet_generator(input_nc, output_nc, num_downs, ngf, use_dropout=True):
    block = UnetSkipConnectionBlock(ngf * 8, ngf * 8, innermost=True)
    for _ in range(num_downs - 5):
        block = UnetSkipConnectionBlock(ngf * 8, ngf * 8, submodule=block, use_dropout=use_dropout)
    block = UnetSkipConnectionBlock(ngf * 4, ngf * 8, submodule=block)
    block = UnetSkipConnectionBlock(ngf * 2, ngf * 4, submodule=block)
    block = UnetSkipConnectionBlock(ngf, ngf * 2, submodule=block)
    return UnetSkipConnectionBlock(output_nc, ngf, input_nc=input_nc, submodule=block, outermost=True)


def nlayer_discriminator(input_nc, ndf=64, n_layers=3):
    seq = [nn.Conv2d(input_nc, ndf, 4, 2, 1), nn.LeakyReLU(0.2, True)]
    mult = 1
    for n in range(1, n_layers):
        prev, mult = mult, min(2 ** n, 8)
        seq += [nn.Conv2d(ndf * prev, ndf * mult, 4, 2, 1, bias=False), nn.BatchNorm2d(ndf * mult),
                nn.LeakyReLU(0.2, True)]
    prev, mult = mult, min(2 ** n_layers, 8)
    seq += [nn.Conv2d(ndf * prev, ndf * mult, 4, 1, 1, bias=False), nn.BatchNorm2d(ndf * mult),
            nn.LeakyReLU(0.2, True), nn.Conv2d(ndf * mult, 1, 4, 1, 1)]
    return nn.Sequential(*seq)


def init_pix2pix(m):
    if isinstance(m, (nn.Conv2d, nn.ConvTranspose2d)):
        nn.init.normal_(m.weight, 0.0, 0.02)
        if m.bias is not None:
            nn.init.zeros_(m.bias)
    elif isinstance(m, nn.BatchNorm2d):
        nn.init.normal_(m.weight, 1.0, 0.02)
        nn.init.zeros_(m.bias)


def bench_gan_iteration(args):
    torch.manual_seed(0)
    S, in_nc, out_nc = args.size, args.in_channels, 3
    G = unet_generator(in_nc, out_nc, args.levels, args.ngf).train()
    D = nlayer_discriminator(in_nc + out_nc, 64, 3).train()
    G.apply(init_pix2pix)
    D.apply(init_pix2pix)
    opt_g = torch.optim.Adam(G.parameters(), lr=2e-4, betas=(0.5, 0.999))
    opt_d = torch.optim.Adam(D.parameters(), lr=2e-4, betas=(0.5, 0.999))
    bce = nn.BCEWithLogitsLoss()
    real_a, real_b = torch.rand(1, in_nc, S, S) * 2 - 1, torch.rand(1, out_nc, S, S) * 2 - 1

    def iteration():  # pix2pix_model.optimize_parameters; autocast around the forward passes
        with autocast(args):
            fake_b = G(real_a)
        for p in D.parameters():
            p.requires_grad_(True)
        opt_d.zero_grad()
        with autocast(args):
            pred_fake = D(torch.cat([real_a, fake_b.detach()], 1))
            pred_real = D(torch.cat([real_a, real_b], 1))
            loss_d = 0.5 * (bce(pred_fake, torch.zeros_like(pred_fake)) + bce(pred_real, torch.ones_like(pred_real)))
        loss_d.backward()
        opt_d.step()
        for p in D.parameters():
            p.requires_grad_(False)
        opt_g.zero_grad()
        with autocast(args):
            pred_fake = D(torch.cat([real_a, fake_b], 1))
            loss_g = bce(pred_fake, torch.ones_like(pred_fake)) + 100.0 * F.l1_loss(fake_b, real_b)
        loss_g.backward()
        opt_g.step()

    emit(f"{S},{args.ngf},{args.levels}", args.threads, timed(iteration, args.reps, args.min_seconds), None)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("key", choices=["sgemm", "conv", "convT", "batchnorm", "nnao_step", "gan_iteration"])
    ap.add_argument("--threads", type=int, required=True)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--min-seconds", type=float, default=0.2)
    ap.add_argument("--shapes", nargs="*", default=[],
                    help="sgemm: M,N,K,TA,TB; conv/convT: Cin,Cout,k,stride,pad,HW; batchnorm: N,C,HW")
    ap.add_argument("--pass", dest="pass_", choices=["fwd", "fwdbwd"], default="fwdbwd")
    ap.add_argument("--window", type=int, default=31, help="nnao_step: input window (features = 4 w^2)")
    ap.add_argument("--batch", type=int, default=16)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--ngf", type=int, default=64)
    ap.add_argument("--levels", type=int, default=8)
    ap.add_argument("--in-channels", type=int, default=12)
    ap.add_argument("--bf16", action="store_true", help="bf16 mm / autocast bf16 (see above)")
    args = ap.parse_args()
    global ARGS
    ARGS = args
    torch.set_num_threads(args.threads)
    torch.set_num_interop_threads(1)
    if args.key == "sgemm":
        bench_sgemm(args)
    elif args.key in ("conv", "convT"):
        bench_conv(args, args.key == "convT")
    elif args.key == "batchnorm":
        bench_batchnorm(args)
    elif args.key == "nnao_step":
        bench_nnao_step(args)
    else:
        bench_gan_iteration(args)


if __name__ == "__main__":
    sys.exit(main())
