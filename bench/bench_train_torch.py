# Description: the PyTorch side of scripts/bench-train: seconds per training epoch of the same sigmoid MLP
# (default 16-48-2 on 83552 random float32 patterns, gain 2/U0) trained by the same algorithm as
# bench/bench_train (momentum back-propagation: dw = momentum * dw - rate * mean gradient; w += dw), written
# several ways so that PyTorch gets its best honest shot, and the sgemm rate of the BLAS it runs on.
#
# One process measures one thread count. scripts/bench-train picks the BLAS and the allocator settings (they
# are fixed when the process starts: LD_LIBRARY_PATH, OPENBLAS_CORETYPE, GLIBC_TUNABLES) and runs this file
# once per thread count and round.
#
# Sample runs:
#   python3 bench/bench_train_torch.py --threads 1
#   LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/openblas-openmp python3 bench/bench_train_torch.py --threads 2 \
#       --only sgemm,inplace-tiled-full-batch
#
# Writes, like bench_train, one line per measurement to stdout:
#   blas threads=T name=... library=... core=... parallel=...    what BLAS this process loaded
#   torch threads=T version=... capability=... allocator=...     the ATen kernel set and the allocator in use
#   sgemm threads=T gflops=<best> samples=<r1,r2,...>             torch.mm on n x n float32 (BLAS sgemm)
#   <variant> threads=T sec_per_epoch=<best> samples=<s1,...> minflt_per_epoch=<f> loss=<l>
# Samples are seconds per epoch of each timed block, after warm-up epochs that are not timed; minflt_per_epoch
# counts the minor page faults per timed epoch: memory the allocator gave back and had to fault in again.
#
# Variants (full batch = one update per epoch; mini-batch = shuffled every epoch; online = one per pattern):
#   autograd-full-batch       idiomatic PyTorch: nn.functional.linear, autograd, optim.SGD(momentum)
#   inplace-full-batch        hand-written forward and backward into preallocated buffers, in-place ops,
#                             no autograd: nothing is allocated per epoch
#   inplace-tiled-full-batch  the same over tiles of --tile patterns that stay in cache, the gradient
#                             accumulated across tiles and applied once: still one full-batch update
#   inplace-mini-batch        the in-place kernel per mini-batch, the data gathered in shuffled order into a
#                             preallocated copy every epoch (index_select with out=)
#   torchscript-online        the per-pattern update as one TorchScript loop (no Python per pattern),
#                             timed on --online-patterns patterns and scaled to an epoch
#   autograd-online           idiomatic per-pattern autograd + optim.SGD, timed and scaled the same way
# Before timing, the hand-written kernels are checked against autograd (and TorchScript against them) on a
# small float64 problem; a mismatch exits 1, so a fast but wrong variant is never timed.
import argparse
import concurrent.futures
import ctypes
import math
import os
import resource
import sys
import time

import torch

ap = argparse.ArgumentParser(prog="bench_train_torch.py")
ap.add_argument("--threads", type=int, default=1)
ap.add_argument("--patterns", type=int, default=83552)
ap.add_argument("--inputs", type=int, default=16)
ap.add_argument("--hidden", type=int, default=48)
ap.add_argument("--outputs", type=int, default=2)
ap.add_argument("--u0", type=float, default=2.0)
ap.add_argument("--mini-batch", type=int, default=1024)
ap.add_argument("--tile", type=int, default=8192, help="patterns per tile of inplace-tiled-full-batch")
ap.add_argument("--online-patterns", type=int, default=2000,
                help="online variants are timed on this many patterns and scaled to an epoch")
ap.add_argument("--repeats", type=int, default=5, help="timed blocks per variant")
ap.add_argument("--block-seconds", type=float, default=0.1, help="a timed block has enough epochs to last this long")
ap.add_argument("--sgemm-n", type=int, default=1024)
ap.add_argument("--split", type=int, default=1,
                help="in-place variants: split each batch over this many Python threads, each running ops with "
                     "threads/split intra-op threads (their names get -split<k>)")
ap.add_argument("--only", default="", help="comma-separated: sgemm and variant names (default: all)")
a = ap.parse_args()

GAIN = 2.0 / a.u0  # Eq 12: f(x) = 1 / (1 + exp(-2 x / U0))
LR, MOMENTUM = 0.01, 0.9
if a.threads < 1 or a.split < 1 or a.threads % a.split:
    sys.exit("bench_train_torch: --threads must be a positive multiple of --split")
torch.set_num_threads(a.threads // a.split)  # new threads take ATen's global setting
P, I, H, O = a.patterns, a.inputs, a.hidden, a.outputs


def emit(line):
    print(line, flush=True)


def loaded_libraries():
    paths = set()
    with open("/proc/self/maps") as maps:
        for line in maps:
            fields = line.split()
            if len(fields) >= 6 and fields[5].startswith("/"):
                paths.add(fields[5])
    return paths


def describe_blas():
    """The BLAS this process really loaded (whatever the system's libblas.so.3 alternative says)."""
    libs = loaded_libraries()
    openblas = sorted(p for p in libs if "libopenblas" in os.path.basename(p))
    blas = sorted(p for p in libs if os.path.basename(p).startswith(("libblas.so", "libblis", "libmkl")))
    if openblas:
        lib = ctypes.CDLL(openblas[0])
        lib.openblas_get_config.restype = ctypes.c_char_p
        lib.openblas_get_corename.restype = ctypes.c_char_p
        config = lib.openblas_get_config().decode()
        parallel = {0: "serial", 1: "pthread", 2: "openmp"}.get(lib.openblas_get_parallel(), "?")
        name = "OpenBLAS " + config.split()[1] if config.startswith("OpenBLAS") else config
        return name, openblas[0], lib.openblas_get_corename().decode(), parallel
    if blas:
        path = os.path.realpath(blas[0])
        if "blis" in path:
            return "BLIS", path, "-", "-"
        if "mkl" in path:
            return "MKL", path, "-", "-"
        return "reference BLAS (Netlib)", path, "-", "-"
    return "none found", "-", "-", "-"


def allocator():
    if any("libjemalloc" in os.path.basename(p) for p in loaded_libraries()):
        return "jemalloc"
    return "glibc" + ("(" + os.environ["GLIBC_TUNABLES"] + ")" if "malloc" in os.environ.get("GLIBC_TUNABLES", "") else "")


def capability():
    for line in torch.__config__.show().splitlines():
        if "CPU capability usage" in line:
            return line.split(":", 1)[1].strip()
    return "?"


def minflt():
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def measure(name, epoch, loss=lambda: float("nan"), scale=1.0):
    """Warm-up epochs (not timed) until 2 epochs and 0.1 s have passed, then --repeats blocks of epochs."""
    start, warm = time.perf_counter(), 0
    while warm < 2 or time.perf_counter() - start < 0.1:
        epoch()
        warm += 1
    per_epoch = (time.perf_counter() - start) / warm
    epochs = max(1, min(50, math.ceil(a.block_seconds / per_epoch)))
    samples = []
    faults = minflt()
    for _ in range(a.repeats):
        t0 = time.perf_counter()
        for _ in range(epochs):
            epoch()
        samples.append((time.perf_counter() - t0) / epochs * scale)
    faults = (minflt() - faults) / (a.repeats * epochs)
    emit("%s threads=%d sec_per_epoch=%.6g samples=%s minflt_per_epoch=%.0f loss=%.4g"
         % (name, a.threads, min(samples), ",".join("%.6g" % s for s in samples), faults, loss()))


def new_parameters(dtype=torch.float32, seed=1):
    g = torch.Generator().manual_seed(seed)
    w1 = (torch.rand(H, I, generator=g, dtype=dtype) * 0.6 - 0.3)
    w2 = (torch.rand(O, H, generator=g, dtype=dtype) * 0.6 - 0.3)
    return [w1, torch.zeros(H, dtype=dtype), w2, torch.zeros(O, dtype=dtype)]  # biases: -theta of Eq 13


def forward(p, xb):
    h = torch.sigmoid(GAIN * torch.nn.functional.linear(xb, p[0], p[1]))  # Eqs 12-13
    return torch.sigmoid(GAIN * torch.nn.functional.linear(h, p[2], p[3]))


class Accumulator:
    """Sums of the gradient of E = 1/2 |o - t|^2 (Eq 14) and of E over rows of a batch, in preallocated
    buffers with in-place ops, in tiles of at most `tile` rows (cache-sized tiles: each tile goes forward and
    backward while its activations are still in cache)."""

    def __init__(self, params, tile, dtype):
        self.p = params
        self.g = [torch.zeros_like(q) for q in params]
        self.tile = tile
        self.h, self.t1, self.dh = (torch.empty(tile, H, dtype=dtype) for _ in range(3))
        self.o, self.e, self.d2 = (torch.empty(tile, O, dtype=dtype) for _ in range(3))
        self.ones = torch.ones(tile, dtype=dtype)
        self.sq = torch.zeros((), dtype=dtype)
        self.loss = torch.zeros((), dtype=dtype)

    def run(self, xb, yb):
        w1, b1, w2, b2 = self.p
        gw1, gb1, gw2, gb2 = self.g
        for g in self.g:
            g.zero_()
        self.loss.zero_()
        for s in range(0, xb.shape[0], self.tile):
            x, y = xb[s:s + self.tile], yb[s:s + self.tile]
            n = x.shape[0]
            h, t1, dh, o, e, d2 = (b[:n] for b in (self.h, self.t1, self.dh, self.o, self.e, self.d2))
            torch.addmm(b1, x, w1.t(), beta=GAIN, alpha=GAIN, out=h)
            h.sigmoid_()
            torch.addmm(b2, h, w2.t(), beta=GAIN, alpha=GAIN, out=o)
            o.sigmoid_()
            torch.sub(o, y, out=e)
            torch.dot(e.view(-1), e.view(-1), out=self.sq)
            self.loss.add_(self.sq)
            torch.mul(o, o, out=d2)
            torch.sub(o, d2, out=d2)
            d2.mul_(e)  # output delta / GAIN: (o - t) o (1 - o)
            gw2.addmm_(d2.t(), h)
            gb2.addmv_(d2.t(), self.ones[:n])
            torch.mm(d2, w2, out=dh)
            torch.mul(h, h, out=t1)
            torch.sub(h, t1, out=t1)
            dh.mul_(t1)  # hidden delta / GAIN^2
            gw1.addmm_(dh.t(), x)
            gb1.addmv_(dh.t(), self.ones[:n])


class InPlace:
    """Momentum back-propagation of the 2-layer sigmoid MLP with every buffer preallocated.

    step(xb, yb) is one update from the mean gradient over the rows of xb. With a pool of k threads the rows
    are split into k contiguous parts, each accumulated by its own thread into its own buffers (PyTorch ops
    release the GIL while they run), and the k sums are added in a fixed order before the update."""

    def __init__(self, params, tile, dtype=torch.float32, pool=None, parts=1):
        self.p = params
        self.v = [torch.zeros_like(q) for q in params]
        self.acc = [Accumulator(params, tile, dtype) for _ in range(parts)]
        self.pool = pool
        self.loss = self.acc[0].loss

    def step(self, xb, yb):
        n_all = xb.shape[0]
        if len(self.acc) == 1:
            self.acc[0].run(xb, yb)
        else:
            k = len(self.acc)
            bounds = [n_all * i // k for i in range(k + 1)]
            for f in [self.pool.submit(acc.run, xb[bounds[i]:bounds[i + 1]], yb[bounds[i]:bounds[i + 1]])
                      for i, acc in enumerate(self.acc)]:
                f.result()
            for acc in self.acc[1:]:
                for g, part in zip(self.acc[0].g, acc.g):
                    g.add_(part)
                self.loss.add_(acc.loss)
        rate2, rate1 = -LR * GAIN / n_all, -LR * GAIN * GAIN / n_all
        for q, v, g, rate in zip(self.p, self.v, self.acc[0].g, (rate1, rate1, rate2, rate2)):
            v.mul_(MOMENTUM).add_(g, alpha=rate)
            q.add_(v)


@torch.jit.script
def online_epoch(x, y, w1, b1, w2, b2, v1, vb1, v2, vb2, h, o, e, d2, dh, t1,
                 gain: float, rate: float, momentum: float, count: int):
    """count online updates, one per row of x in order: the TorchScript loop runs no Python per pattern."""
    for i in range(count):
        xi = x[i]
        torch.addmv(b1, w1, xi, beta=gain, alpha=gain, out=h)
        h.sigmoid_()
        torch.addmv(b2, w2, h, beta=gain, alpha=gain, out=o)
        o.sigmoid_()
        torch.sub(o, y[i], out=e)
        torch.mul(o, o, out=d2)
        torch.sub(o, d2, out=d2)
        d2.mul_(e)
        torch.mv(w2.t(), d2, out=dh)
        torch.mul(h, h, out=t1)
        torch.sub(h, t1, out=t1)
        dh.mul_(t1)
        v2.mul_(momentum).addr_(d2, h, alpha=-rate * gain)
        vb2.mul_(momentum).add_(d2, alpha=-rate * gain)
        v1.mul_(momentum).addr_(dh, xi, alpha=-rate * gain * gain)
        vb1.mul_(momentum).add_(dh, alpha=-rate * gain * gain)
        w2.add_(v2)
        b2.add_(vb2)
        w1.add_(v1)
        b1.add_(vb1)


class Online:
    def __init__(self, params, dtype=torch.float32):
        self.p = params
        self.v = [torch.zeros_like(q) for q in params]
        self.bufs = [torch.empty(H, dtype=dtype)] + [torch.empty(O, dtype=dtype) for _ in range(3)] + \
                    [torch.empty(H, dtype=dtype) for _ in range(2)]

    def run(self, x, y, count):
        online_epoch(x, y, *self.p, *self.v, *self.bufs, GAIN, LR, MOMENTUM, count)


def check_kernels():
    """The hand-written gradients against autograd, and the TorchScript loop against them, in float64."""
    g = torch.Generator().manual_seed(7)
    n = 37
    x = torch.rand(n, I, generator=g, dtype=torch.float64) * 2 - 1
    y = torch.rand(n, O, generator=g, dtype=torch.float64) * 0.8 + 0.1
    # Two updates with autograd and the same momentum rule.
    ref = [q.clone().requires_grad_() for q in new_parameters(torch.float64)]
    vel = [torch.zeros_like(q) for q in ref]
    for _ in range(2):
        loss = 0.5 * ((forward(ref, x) - y) ** 2).sum() / n
        grads = torch.autograd.grad(loss, ref)
        with torch.no_grad():
            for q, v, gr in zip(ref, vel, grads):
                v.mul_(MOMENTUM).add_(gr, alpha=-LR)
                q.add_(v)
    pool = concurrent.futures.ThreadPoolExecutor(3)
    for tile, parts in ((n, 1), (8, 1), (8, 3)):  # one tile, several, several in each of 3 threads
        k = InPlace(new_parameters(torch.float64), tile, torch.float64, pool, parts)
        for _ in range(2):
            k.step(x, y)
        for q, r in zip(k.p, ref):
            if not torch.allclose(q, r.detach(), rtol=0, atol=1e-12):
                sys.exit("bench_train_torch: in-place kernel (tile %d, %d parts) disagrees with autograd by %g"
                         % (tile, parts, (q - r.detach()).abs().max().item()))
    pool.shutdown()
    # Online: three single-pattern updates in order, by the in-place kernel and by TorchScript.
    k = InPlace(new_parameters(torch.float64), 1, torch.float64)
    for i in range(3):
        k.step(x[i:i + 1], y[i:i + 1])
    s = Online(new_parameters(torch.float64), torch.float64)
    s.run(x, y, 3)
    for q, r in zip(s.p, k.p):
        if not torch.allclose(q, r, rtol=0, atol=1e-12):
            sys.exit("bench_train_torch: TorchScript online loop disagrees with the in-place kernel by %g"
                     % (q - r).abs().max().item())


def main():
    wanted = set(filter(None, a.only.split(",")))
    want = lambda name: not wanted or name in wanted
    name, path, core, parallel = describe_blas()
    emit("blas threads=%d name=%s library=%s core=%s parallel=%s"
         % (a.threads, name.replace(" ", "_"), path, core, parallel))
    emit("torch threads=%d version=%s capability=%s torch_threads=%d allocator=%s"
         % (a.threads, torch.__version__, capability(), torch.get_num_threads(), allocator()))
    check_kernels()

    if want("sgemm"):
        n = a.sgemm_n
        m1, m2, out = torch.rand(n, n), torch.rand(n, n), torch.empty(n, n)
        torch.mm(m1, m2, out=out)  # warm-up: thread start-up, page faults
        rates = []
        for _ in range(a.repeats):
            t0 = time.perf_counter()
            torch.mm(m1, m2, out=out)
            rates.append(2.0 * n ** 3 / (time.perf_counter() - t0) * 1e-9)
        emit("sgemm threads=%d gflops=%.1f samples=%s n=%d"
             % (a.threads, max(rates), ",".join("%.1f" % r for r in rates), n))

    torch.manual_seed(0)
    x = torch.rand(P, I) * 2 - 1  # inputs in [-1, 1], targets in [0.1, 0.9], as bench_train
    y = torch.rand(P, O) * 0.8 + 0.1

    if want("autograd-full-batch"):
        p = [q.requires_grad_() for q in new_parameters()]
        # torch's SGD keeps v = m v + g and steps w -= lr v: the same update as dw = m dw - lr g.
        opt = torch.optim.SGD(p, lr=LR, momentum=MOMENTUM)
        last = [float("nan")]

        def epoch():
            opt.zero_grad()
            loss = ((forward(p, x) - y) ** 2).sum() * (0.5 / P)
            loss.backward()
            opt.step()
            last[0] = loss.item()
        measure("pytorch-autograd-full-batch", epoch, lambda: last[0])
        del p, opt

    pool = concurrent.futures.ThreadPoolExecutor(a.split) if a.split > 1 else None
    split = "-split%d" % a.split if a.split > 1 else ""
    for variant, tile in (("inplace-full-batch", -(-P // a.split)), ("inplace-tiled-full-batch", min(a.tile, P))):
        if want(variant):
            k = InPlace(new_parameters(), tile, pool=pool, parts=a.split)
            measure("pytorch-" + variant + split, lambda: k.step(x, y), lambda: k.loss.item() * 0.5 / P)
            del k

    if want("inplace-mini-batch"):
        b = min(a.mini_batch, P)
        k = InPlace(new_parameters(), -(-b // a.split), pool=pool, parts=a.split)
        xs, ys = torch.empty_like(x), torch.empty_like(y)
        order = torch.empty(P, dtype=torch.long)
        gen = torch.Generator().manual_seed(3)

        def epoch():
            torch.randperm(P, generator=gen, out=order)
            torch.index_select(x, 0, order, out=xs)
            torch.index_select(y, 0, order, out=ys)
            for s in range(0, P, b):
                k.step(xs[s:s + b], ys[s:s + b])
        measure("pytorch-inplace-mini-batch" + split, epoch)
        del k

    count = min(a.online_patterns, P)
    if want("torchscript-online"):
        s = Online(new_parameters())
        measure("pytorch-torchscript-online", lambda: s.run(x, y, count), scale=P / count)

    if want("autograd-online"):
        p = [q.requires_grad_() for q in new_parameters()]
        opt = torch.optim.SGD(p, lr=LR, momentum=MOMENTUM)

        def epoch():
            for i in range(count):
                opt.zero_grad()
                loss = 0.5 * ((forward(p, x[i:i + 1]) - y[i:i + 1]) ** 2).sum()
                loss.backward()
                opt.step()
        measure("pytorch-autograd-online", epoch, scale=P / count)


if __name__ == "__main__":
    main()
