#!/usr/bin/env python3
"""Convert the IMO reference release's PyTorch checkpoint to an hdvio .tcn (version 4) file.

The release (uzh-rpg/learned_inertial_model_odometry, results/<dataset>/checkpoints/model_net/
*.pt) stores {"model_state_dict": ...} of a residual TCN (Bai et al. 2018 blocks: two
weight-normalized causal convolutions with GELU, ReLU after the residual sum, dilation 2^i,
a linear head on the last step) whose inputs are [gyro; thrust] rotated to the world frame,
sampled at t_begin + k / rate (k = 0 .. N-1). docs/imo_network.md describes the mapping.

What the conversion does:
  * folds weight norm in: w = g * v / ||v|| (norm over all but the output dimension);
  * reorders the first block's input channels to hdvio's [thrust; gyro];
  * writes identity input normalization (the release has none), output_sigma none,
    "sample_times begin", block_relu 1, window_padding 1.

It reads the checkpoint with the Python standard library only (zip + pickle, no torch), so
it runs anywhere. Usage:
  convert_imo_release_checkpoint.py <net.pt> <out.tcn> [--window 50] [--rate 100]
      [--encoding float32|text]
Bad input (not a checkpoint, unexpected tensors or shapes, non-finite numbers) prints
"error: <file>:0: <problem>" and exits 2 without writing <out.tcn>.
"""
import argparse
import math
import os
import pickle
import struct
import sys
import zipfile


class ConversionError(Exception):
    pass


class _Storage:
    def __init__(self, dtype, key, numel):
        self.dtype, self.key, self.numel = dtype, key, numel


class _Tensor:
    """A float32 tensor: flat values (row-major) and shape."""

    def __init__(self, values, shape):
        self.values, self.shape = values, tuple(shape)


class _Ignored:
    """Stands for anything in the checkpoint that is not a model tensor (optimizer state...)."""

    def __init__(self, *args, **kwargs):
        pass

    def __setstate__(self, state):
        pass


_STORAGE_TYPES = {"FloatStorage": "f", "DoubleStorage": "d", "HalfStorage": "e"}


def _read_checkpoint(path):
    try:
        archive = zipfile.ZipFile(path)
    except (zipfile.BadZipFile, OSError) as e:
        raise ConversionError("not a PyTorch zip checkpoint (%s)" % e)
    names = archive.namelist()
    pkl = [n for n in names if n.endswith("/data.pkl")]
    if len(pkl) != 1:
        raise ConversionError("not a PyTorch checkpoint (no <archive>/data.pkl)")
    prefix = pkl[0][: -len("data.pkl")]
    storages = {}

    def load_storage(s):
        if s.key not in storages:
            name = prefix + "data/" + s.key
            if name not in names:
                raise ConversionError("storage %s missing from the archive" % s.key)
            raw = archive.read(name)
            size = struct.calcsize("<" + s.dtype)
            if len(raw) != size * s.numel:
                raise ConversionError("storage %s has %d bytes, expected %d" % (s.key, len(raw), size * s.numel))
            storages[s.key] = struct.unpack("<%d%s" % (s.numel, s.dtype), raw)
        return storages[s.key]

    def rebuild_tensor(storage, offset, size, stride, *rest):
        if not isinstance(storage, _Storage):
            return _Ignored()
        data = load_storage(storage)
        shape = tuple(size)
        values = []
        # General strided gather (checkpoints are contiguous, but do not rely on it).
        def walk(dim, base):
            if dim == len(shape):
                values.append(float(data[base]))
                return
            for i in range(shape[dim]):
                walk(dim + 1, base + i * stride[dim])
        walk(0, offset)
        return _Tensor(values, shape)

    class Unpickler(pickle.Unpickler):
        def find_class(self, module, name):
            if module == "collections" and name == "OrderedDict":
                import collections
                return collections.OrderedDict
            if module == "torch._utils" and name == "_rebuild_tensor_v2":
                return rebuild_tensor
            if module == "torch._utils" and name == "_rebuild_parameter":
                return lambda t, *rest: t
            if module == "torch" and name in _STORAGE_TYPES:
                return _STORAGE_TYPES[name]
            return _Ignored

        def persistent_load(self, pid):
            if not (isinstance(pid, tuple) and len(pid) >= 5 and pid[0] == "storage"):
                raise ConversionError("unexpected persistent id in the checkpoint")
            dtype = pid[1] if isinstance(pid[1], str) else None
            return _Storage(dtype, str(pid[2]), int(pid[4])) if dtype else _Ignored()

    try:
        obj = Unpickler(archive.open(pkl[0])).load()
    except ConversionError:
        raise
    except Exception as e:  # a corrupt pickle can raise almost anything
        raise ConversionError("cannot read the checkpoint's pickle (%s: %s)" % (type(e).__name__, e))
    if isinstance(obj, dict) and "model_state_dict" in obj:
        obj = obj["model_state_dict"]
    if not isinstance(obj, dict):
        raise ConversionError("the checkpoint holds no state dict (expected {'model_state_dict': ...})")
    return obj


def _get(state, key, shape=None):
    t = state.get(key)
    if not isinstance(t, _Tensor):
        raise ConversionError("tensor '%s' missing" % key)
    if shape is not None and t.shape != tuple(shape):
        raise ConversionError("tensor '%s' has shape %s, expected %s" % (key, list(t.shape), list(shape)))
    for v in t.values:
        if not math.isfinite(v):
            raise ConversionError("tensor '%s' holds a non-finite number" % key)
    return t


def _fold_weight_norm(g, v):
    """w[o] = g[o] * v[o] / ||v[o]|| (torch weight_norm, dim 0)."""
    out, per = v.shape[0], len(v.values) // v.shape[0]
    if len(g.values) != out:
        raise ConversionError("weight_g does not match weight_v")
    w = []
    for o in range(out):
        row = v.values[o * per:(o + 1) * per]
        n = math.sqrt(sum(x * x for x in row))
        if n == 0.0:
            raise ConversionError("weight_v has a zero row")
        w.extend(g.values[o] * x / n for x in row)
    return _Tensor(w, v.shape)


def _conv_matrix(w, perm=None):
    """torch (out, in, k) -> hdvio rows out x cols k*in, column j*in + i = w[o][i][j]."""
    out, cin, k = w.shape
    src = perm if perm is not None else list(range(cin))
    rows = []
    for o in range(out):
        rows.append([w.values[(o * cin + src[i]) * k + j] for j in range(k) for i in range(cin)])
    return rows


def convert(state, window, rate):
    """Returns (header lines, tensors [(kind, name, rows)]) of the hdvio file."""
    blocks = 0
    while "tcn.network.%d.conv1.weight_v" % blocks in state:
        blocks += 1
    if blocks == 0:
        raise ConversionError("no 'tcn.network.<i>.conv1.weight_v': not the release's TCN")
    expected = set()
    layers, tensors = [], []
    cin = None
    # The release feeds [gyro(3); thrust(3)]; hdvio's rows are [thrust(3); gyro(3)].
    perm = [3, 4, 5, 0, 1, 2]
    tensors.append(("vector", "input_mean", [[0.0] * 6]))
    tensors.append(("vector", "input_std", [[1.0] * 6]))
    kernel = None
    for b in range(blocks):
        p = "tcn.network.%d." % b
        convs = []
        for c in ("conv1", "conv2"):
            v = _get(state, p + c + ".weight_v")
            if len(v.shape) != 3:
                raise ConversionError("'%s%s.weight_v' is not a 1-D convolution" % (p, c))
            g = _get(state, p + c + ".weight_g", (v.shape[0], 1, 1))
            bias = _get(state, p + c + ".bias", (v.shape[0],))
            expected |= {p + c + ".weight_v", p + c + ".weight_g", p + c + ".bias"}
            # nn.Sequential registers the same parameters again as net.0 / net.4.
            alias = p + ("net.0." if c == "conv1" else "net.4.")
            for part, t in (("weight_v", v), ("weight_g", g), ("bias", bias)):
                if alias + part in state:
                    a = _get(state, alias + part, t.shape)
                    if a.values != t.values:
                        raise ConversionError("'%s%s' differs from '%s%s.%s'" % (alias, part, p, c, part))
                    expected.add(alias + part)
            convs.append((_fold_weight_norm(g, v), bias))
        out = convs[0][0].shape[0]
        if b == 0:
            cin = convs[0][0].shape[1]
            if cin != 6:
                raise ConversionError("the first block has %d inputs, expected 6 (gyro, thrust)" % cin)
        if kernel is None:
            kernel = convs[0][0].shape[2]
        width_in = cin if b == 0 else layers[-1][0]
        if convs[0][0].shape != (out, width_in, kernel) or convs[1][0].shape != (out, out, kernel):
            raise ConversionError("block %d's convolution shapes do not chain" % b)
        for j, (w, bias) in enumerate(convs):
            n = 2 * b + j
            tensors.append(("matrix", "conv%d.weight" % n, _conv_matrix(w, perm if (b == 0 and j == 0) else None)))
            tensors.append(("vector", "conv%d.bias" % n, [bias.values]))
        if p + "downsample.weight" in state:
            dw = _get(state, p + "downsample.weight", (out, width_in, 1))
            db = _get(state, p + "downsample.bias", (out,))
            expected |= {p + "downsample.weight", p + "downsample.bias"}
            tensors.append(("matrix", "skip%d.weight" % b, _conv_matrix(dw, perm if b == 0 else None)))
            tensors.append(("vector", "skip%d.bias" % b, [db.values]))
        elif out != width_in:
            raise ConversionError("block %d changes width without a downsample convolution" % b)
        layers.append((out, 2 ** b))
    lw = _get(state, "linear.weight", (3, layers[-1][0]))
    lb = _get(state, "linear.bias", (3,))
    expected |= {"linear.weight", "linear.bias"}
    rows = [lw.values[o * layers[-1][0]:(o + 1) * layers[-1][0]] for o in range(3)]
    tensors.append(("matrix", "head.weight", rows))
    tensors.append(("vector", "head.bias", [lb.values]))
    extra = sorted(k for k, v in state.items() if isinstance(v, _Tensor) and k not in expected)
    if extra:
        raise ConversionError("unexpected tensors for the release's TCN: %s" % ", ".join(extra[:5]))
    header = [
        "task displacement", "inputs thrust_gyro", "output_sigma none", "drag_law none",
        "sample_times begin", "input_channels 6", "kernel_size %d" % kernel, "window %d" % window,
        "sample_rate_hz %.17g" % rate, "variance_head 0", "residual 1", "block_relu 1",
        "window_padding 1", "layers %d" % len(layers),
    ] + ["layer %d %d" % l for l in layers]
    return header, tensors


def format_file(header, tensors, comment, encoding):
    lines = ["hdvio_tcn 4"] + ["# " + c for c in comment] + header
    lines.append("encoding " + encoding)
    text = "\n".join(lines) + "\n"
    if encoding == "text":
        body = []
        for kind, name, rows in tensors:
            if kind == "vector":
                body.append("vector %s %d" % (name, len(rows[0])))
            else:
                body.append("matrix %s %d %d" % (name, len(rows), len(rows[0])))
            for r in rows:
                body.append(" ".join("%.9g" % struct.unpack("<f", struct.pack("<f", x))[0] for x in r))
        return (text + "\n".join(body) + "\nend\n").encode()
    flat = [x for _, _, rows in tensors for r in rows for x in r]
    return (text + "data %d\n" % len(flat)).encode() + struct.pack("<%df" % len(flat), *flat) + b"\nend\n"


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("checkpoint")
    ap.add_argument("out")
    ap.add_argument("--window", type=int, default=50, help="input samples (release: window_time * sampling_freq)")
    ap.add_argument("--rate", type=float, default=100.0, help="input sample rate, Hz")
    ap.add_argument("--encoding", choices=["float32", "text"], default="float32")
    args = ap.parse_args(argv)
    try:
        if not os.path.isfile(args.checkpoint):
            raise ConversionError("cannot open the checkpoint")
        if args.window < 1 or not (args.rate > 0):
            raise ConversionError("--window and --rate must be positive")
        header, tensors = convert(_read_checkpoint(args.checkpoint), args.window, args.rate)
    except ConversionError as e:
        print("error: %s:0: %s" % (args.checkpoint, e), file=sys.stderr)
        return 2
    comment = ["converted by scripts/convert_imo_release_checkpoint.py from " + os.path.basename(args.checkpoint),
               "(IMO reference release TCN; weight norm folded, inputs reordered to thrust, gyro)"]
    data = format_file(header, tensors, comment, args.encoding)
    tmp = args.out + ".tmp"
    try:
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, args.out)
    except OSError as e:
        print("error: %s:0: cannot write (%s)" % (args.out, e.strerror), file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
