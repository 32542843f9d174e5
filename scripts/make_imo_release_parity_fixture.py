#!/usr/bin/python3
"""Make the parity fixture of the IMO release's TCN variant (needs torch: apt-get install
python3-torch; run with /usr/bin/python3). Writes, into <out_dir>:

  imo_release_tiny.pt              a tiny randomly initialized network of the release's
                                   architecture, saved as the release saves its checkpoints
                                   ({"model_state_dict": ...}, the same tensor names)
  imo_release_tiny_reference.txt   input windows (hdvio row order: thrust, gyro) and the
                                   torch outputs for them

The release's block (Bai et al. 2018, as in TLIO): two weight-normalized causal dilated
convolutions with GELU, a 1x1 convolution skip when the width changes, ReLU after the sum;
dilation 2^i; a linear head on the last time step; inputs [gyro; thrust]. Here widths
[4, 4, 8], kernel 2, receptive field 15 on a 10-sample window, so the padding matters.
The C++ test (test/learned/imo_release_tcn_test.cc) checks hdvio's Eigen TCN on the
converted file against these outputs; test/learned/check_release_converter.sh checks that
the converter still turns the .pt into the committed .tcn.
"""
import os
import sys

import torch
import torch.nn as nn
import torch.nn.functional as F
from torch.nn.utils import weight_norm

WIDTHS = [4, 4, 8]
KERNEL = 2
WINDOW = 10
WINDOWS = 4


class Block(nn.Module):
    def __init__(self, cin, cout, dilation):
        super().__init__()
        self.dilation = dilation
        self.conv1 = weight_norm(nn.Conv1d(cin, cout, KERNEL, dilation=dilation))
        self.conv2 = weight_norm(nn.Conv1d(cout, cout, KERNEL, dilation=dilation))
        # The release registers both convolutions again in an nn.Sequential at positions 0
        # and 4; the same aliases keep the checkpoint's tensor names.
        self.net = nn.ModuleList([self.conv1, nn.Identity(), nn.Identity(), nn.Identity(), self.conv2])
        self.downsample = nn.Conv1d(cin, cout, 1) if cin != cout else None

    def causal(self, conv, x):
        return conv(F.pad(x, ((KERNEL - 1) * self.dilation, 0)))

    def forward(self, x):
        h = F.gelu(self.causal(self.conv1, x))
        y = F.gelu(self.causal(self.conv2, h))
        return F.relu(y + (x if self.downsample is None else self.downsample(x)))


class Network(nn.Module):
    def __init__(self):
        super().__init__()
        blocks, cin = [], 6
        for i, w in enumerate(WIDTHS):
            blocks.append(Block(cin, w, 2 ** i))
            cin = w
        self.tcn = nn.Module()
        self.tcn.network = nn.Sequential(*blocks)
        self.linear = nn.Linear(cin, 3)

    def forward(self, x):  # x: batch x 6 [gyro; thrust] x time
        return self.linear(self.tcn.network(x)[:, :, -1])


def main(out_dir):
    torch.manual_seed(21)
    net = Network()
    with torch.no_grad():  # weights large enough that GELU / ReLU are far from linear
        for name, p in net.named_parameters():
            if name.endswith("weight_g"):
                p.uniform_(0.5, 1.5)
            else:
                p.normal_(0.0, 0.6)
    net.eval()
    torch.save({"model_state_dict": net.state_dict(), "epoch": 0},
               os.path.join(out_dir, "imo_release_tiny.pt"))
    x = torch.randn(WINDOWS, 6, WINDOW) * 2.0
    with torch.no_grad():
        y = net(x)
    with open(os.path.join(out_dir, "imo_release_tiny_reference.txt"), "w") as f:
        f.write("# scripts/make_imo_release_parity_fixture.py, torch %s\n" % torch.__version__)
        f.write("# per window: 6 rows [thrust xyz; gyro xyz] x %d samples, then the torch output\n" % WINDOW)
        f.write("windows %d samples %d\n" % (WINDOWS, WINDOW))
        for b in range(WINDOWS):
            hdvio_rows = torch.cat([x[b, 3:6], x[b, 0:3]], dim=0)  # release [gyro; thrust]
            for r in hdvio_rows:
                f.write(" ".join("%.9g" % v for v in r.tolist()) + "\n")
            f.write(" ".join("%.9g" % v for v in y[b].tolist()) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "test/learned/data"))
