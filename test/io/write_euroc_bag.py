#!/usr/bin/python3
"""Writes an ASL (EuRoC) folder as a EuRoC-style ROS 1 bag with Debian's python3-rosbag, an
implementation independent of hdvio's reader. Used by io_euroc_bag_test.

usage: write_euroc_bag.py <mav0 folder> <out.bag> [none|bz2|lz4]
Topics as in EuRoC's own bags: /imu0 (sensor_msgs/Imu), /cam0/image_raw (sensor_msgs/Image,
mono8), /vicon/firefly_sbx/firefly_sbx (geometry_msgs/TransformStamped, here the ground-truth
state estimate's pose). Header stamps and record times are the ASL timestamps.
"""
import csv
import os
import sys

import genpy
import rosbag
from geometry_msgs.msg import TransformStamped
from PIL import Image as PilImage
from sensor_msgs.msg import Image, Imu


def rows(path):
    with open(path) as f:
        for row in csv.reader(f):
            if row and not row[0].startswith('#'):
                yield row


def stamp(ns):
    return genpy.Time(int(ns) // 1000000000, int(ns) % 1000000000)


def main():
    mav0, out = sys.argv[1], sys.argv[2]
    compression = sys.argv[3] if len(sys.argv) > 3 else 'none'
    messages = []
    for r in rows(os.path.join(mav0, 'imu0', 'data.csv')):
        m = Imu()
        m.header.stamp = stamp(r[0])
        m.header.frame_id = 'imu4'
        m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = map(float, r[1:4])
        m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z = map(float, r[4:7])
        messages.append((int(r[0]), '/imu0', m))
    for r in rows(os.path.join(mav0, 'cam0', 'data.csv')):
        pixels = PilImage.open(os.path.join(mav0, 'cam0', 'data', r[1].strip()))
        if pixels.mode != 'L':
            pixels = pixels.convert('L')
        m = Image()
        m.header.stamp = stamp(r[0])
        m.header.frame_id = 'cam0'
        m.width, m.height = pixels.size
        m.encoding = 'mono8'
        m.step = m.width
        m.data = pixels.tobytes()
        messages.append((int(r[0]), '/cam0/image_raw', m))
    gt = os.path.join(mav0, 'state_groundtruth_estimate0', 'data.csv')
    if os.path.exists(gt):
        for r in rows(gt):
            m = TransformStamped()
            m.header.stamp = stamp(r[0])
            m.header.frame_id = 'world'
            m.child_frame_id = 'vicon/firefly_sbx/firefly_sbx'
            t, q = m.transform.translation, m.transform.rotation
            t.x, t.y, t.z = map(float, r[1:4])
            q.w, q.x, q.y, q.z = map(float, r[4:8])
            messages.append((int(r[0]), '/vicon/firefly_sbx/firefly_sbx', m))
    messages.sort(key=lambda x: x[0])
    with rosbag.Bag(out, 'w', compression=compression) as bag:
        for ns, topic, m in messages:
            bag.write(topic, m, stamp(ns))


if __name__ == '__main__':
    main()
