#!/usr/bin/env python3
"""White-noise density of an IMU in flight, from the high-frequency band of its raw signals.

Above ~20 Hz a quadrotor's motion has almost no power left; what the accelerometer and gyroscope
show there is sensor noise plus motor/propeller vibration, the noise an estimator has to live
with in flight (larger than a datasheet's bench value). For a white noise of density n (Kalibr
units: m/s^2/sqrt(Hz), rad/s/sqrt(Hz)) the one-sided PSD is 2 n^2, so n = sqrt(mean PSD / 2)
over the band. Welch PSD, 256-sample Hann segments with 50 % overlap.
  imu_vibration_density.py <ASL folder>... [--low_hz 20]
(convert Blackbird / DIDO flights first: hdvio_convert --input <flight> --output <ASL folder>)
"""
import argparse

import numpy as np

from dynamics_noise_calibration import read_csv


def welch(x, fs, n=256):
    w = np.hanning(n)
    segs = [x[i:i + n] - x[i:i + n].mean() for i in range(0, len(x) - n, n // 2)]
    P = np.mean([np.abs(np.fft.rfft(s * w)) ** 2 for s in segs], axis=0) / (fs * (w ** 2).sum()) * 2
    return np.fft.rfftfreq(n, 1 / fs), P


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--low_hz", type=float, default=20.0)
    a = ap.parse_args()
    print("| flight | IMU rate [Hz] | band [Hz] | accel x / y / z [m/s^2/sqrt(Hz)] | gyro x / y / z [rad/s/sqrt(Hz)] |")
    print("|---|---|---|---|---|")
    for folder in a.folders:
        d = read_csv(f"{folder}/mav0/imu0/data.csv", min_cols=7)
        fs = 1.0 / np.median(np.diff(d[:, 0] * 1e-9))
        hi = 0.8 * fs / 2
        dens = []
        for col in range(1, 7):
            f, P = welch(d[:, col], fs)
            band = (f >= a.low_hz) & (f <= hi)
            dens.append(np.sqrt(P[band].mean() / 2))
        g = " / ".join(f"{v:.4f}" for v in dens[:3])
        acc = " / ".join(f"{v:.4f}" for v in dens[3:])
        print(f"| {folder} | {fs:.0f} | {a.low_hz:.0f}-{hi:.0f} | {acc} | {g} |")


if __name__ == "__main__":
    main()
