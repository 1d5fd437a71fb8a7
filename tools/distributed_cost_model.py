#!/usr/bin/env python3
"""The scaling model of docs/distributed.md, from measured per-image times.

    tools/distributed_cost_model.py --gan-ms-per-image T [--nnao-us-per-point U]

T: forward + backward of G and D for one image of the default GAN on one thread, as
measured on this machine (docs/distributed.md says how). Everything else is computed:
parameters and multiply-adds of the pix2pix U-Net and PatchGAN (models/gi/unet.h,
patchgan.h) for the default and the thesis-size (54 M) model; the thesis model's time
per image is T scaled by its multiply-adds (the same throughput per MAC: larger
convolutions usually run faster per MAC, so this errs towards the slow side).

Communication per optimizer step, S = 4 bytes x parameters (G + D), N ranks:
  ring all-reduce (NCCL/PyTorch DDP):   2 (N-1) a + 2 (N-1)/N S / B
  ours, fixed-order chain + broadcast:  2 S / B + 2 (N-1) (a + b / B)   (b: bucket bytes,
                                        pipelined over S / b buckets; the broadcast as a
                                        pipelined chain)
Step time with N ranks: (K / N) t + max(0, comm - overlap), where overlap is the backward
time of a rank's last micro-batch (about 2/3 of t) when buckets start during backward.
"""
import argparse


def unet(cin, ngf, levels, h, w, cout=3):
    ch = [ngf * min(2 ** i, 8) for i in range(levels)]
    macs = params = 0
    prev = cin
    for i in range(levels):
        macs += (h >> (i + 1)) * (w >> (i + 1)) * ch[i] * prev * 16
        params += ch[i] * prev * 16
        prev = ch[i]
    for i in reversed(range(levels)):
        cin_up = ch[i] if i == levels - 1 else 2 * ch[i]
        co = cout if i == 0 else ch[i - 1]
        macs += (h >> i) * (w >> i) * co * cin_up * 16
        params += co * cin_up * 16
    return macs, params


def patchgan(cin, ndf, layers, h, w):
    macs = params = 0
    prev = cin
    for i in range(layers):
        co = ndf * min(2 ** i, 8)
        h, w = h // 2, w // 2
        macs += h * w * co * prev * 16
        params += co * prev * 16
        prev = co
    co = ndf * min(2 ** layers, 8)
    h, w = h - 1, w - 1
    macs += h * w * co * prev * 16
    params += co * prev * 16
    h, w = h - 1, w - 1
    macs += h * w * co * 16
    params += co * 16
    return macs, params


def ring(n, s, a, bw):
    return 2 * (n - 1) * a + 2 * (n - 1) / n * s / bw


def chain(n, s, a, bw, bucket):
    b = min(bucket, s)
    return 2 * s / bw + 2 * (n - 1) * (a + b / bw) if n > 1 else 0.0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--gan-ms-per-image", type=float, required=True)
    ap.add_argument("--batch", type=int, default=64, help="global batch K (images per step)")
    ap.add_argument("--bucket-mb", type=float, default=1.0)
    ap.add_argument("--rank-speedup", type=float, default=1.0,
                    help="how much faster one rank computes an image than the measured thread (e.g. 32 cores at ideal scaling: 32)")
    o = ap.parse_args()
    gd, gp = unet(12, 16, 5, 128, 256)
    dd, dp = patchgan(15, 16, 3, 64, 64)
    td, tp = unet(12, 64, 8, 256, 256)
    tdd, tdp = patchgan(15, 64, 3, 256, 256)
    t_default = o.gan_ms_per_image * 1e-3 / o.rank_speedup
    models = {
        "default GAN (G %.2f M + D %.2f M)" % (gp / 1e6, dp / 1e6): (gp + dp, t_default),
        "thesis-size (G %.1f M + D %.1f M)" % (tp / 1e6, tdp / 1e6): (tp + tdp, t_default * (td + tdd) / (gd + dd)),
    }
    nets = {"10 Gbit/s, 20 us": (20e-6, 10e9 / 8), "100 Gbit/s, 5 us": (5e-6, 100e9 / 8)}
    K = o.batch
    bucket = o.bucket_mb * 1048576
    print("| model | bytes/step | s/image | network | N | ring ms | ours ms | speed-up ring | speed-up ours | ours, no overlap |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, (params, t) in models.items():
        s = 4 * params
        for net, (a, bw) in nets.items():
            for n in (4, 16, 64):
                r, c = ring(n, s, a, bw), chain(n, s, a, bw, bucket)
                compute = K / n * t
                overlap = 2 / 3 * t
                t1 = K * t
                sp = lambda comm, ov: t1 / (compute + max(0.0, comm - ov))
                print(f"| {name} | {s / 1e6:.1f} MB | {t:.3f} | {net} | {n} | {r * 1e3:.1f} | {c * 1e3:.1f} | "
                      f"{sp(r, overlap):.1f} | {sp(c, overlap):.1f} | {sp(c, 0):.1f} |")
    print()
    print("Ranks where the exposed exchange equals the compute per rank (beyond it, adding ranks stops paying):")
    for name, (params, t) in models.items():
        s = 4 * params
        for net, (a, bw) in nets.items():
            comm = chain(64, s, a, bw, bucket)
            print(f"  {name}, {net}: N* = K t / comm = {K * t / comm:.0f} for K = {K}; "
                  f"per-rank batch K/N below {comm / t:.2f} images")


if __name__ == "__main__":
    main()
