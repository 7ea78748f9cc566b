#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
"""ROS 1 bags of Ouster packets for the tests, written and read with Debian's python3-rosbag (the
ROS library itself, independent of our C++ reader), in the layout ouster-ros records:
ouster_ros/PacketMsg (uint8[] buf) on <ns>/lidar_packets and <ns>/imu_packets, the sensor's JSON
as std_msgs/String on <ns>/metadata.

  ouster_bag.py write PACKETS METADATA.json OUT.bag [--ns /os_node] [--no-metadata] [--no-imu]
                      [--also-ns NS]  (a second sensor's topics: the same packets again)
      PACKETS: the test's packet stream, records of <int64 time_ns><uint8 kind (0 lidar,
      1 imu)><uint32 length><payload>, little-endian.
  ouster_bag.py topcap BAG OUT.pcap
      every lidar and IMU packet of the bag as Ethernet/IPv4/UDP records of a nanosecond pcap,
      at its bag record time, on the metadata's ports (else 7502/7503).
"""
import argparse
import io
import json
import struct
import sys

import genpy
import rosbag
from std_msgs.msg import String


class PacketMsg(genpy.Message):
    """ouster_ros/PacketMsg, as its .msg defines it (one field: uint8[] buf)."""
    _md5sum = "4f7b5949e76f86d01e96b0e33ba9b5e3"
    _type = "ouster_ros/PacketMsg"
    _has_header = False
    _full_text = "uint8[] buf\n"
    __slots__ = ["buf"]
    _slot_types = ["uint8[]"]

    def __init__(self, buf=b""):
        self.buf = buf

    def serialize(self, buff):
        buff.write(struct.pack("<I", len(self.buf)))
        buff.write(self.buf)

    def deserialize(self, data):
        (n,) = struct.unpack_from("<I", data, 0)
        self.buf = bytes(data[4:4 + n])
        return self


def write(args):
    meta_text = open(args.metadata).read()
    data = open(args.packets, "rb").read()
    ns = args.ns.rstrip("/")
    with rosbag.Bag(args.out, "w") as bag:
        pos, first = 0, True
        while pos < len(data):
            t_ns, kind, n = struct.unpack_from("<qBI", data, pos)
            pos += 13
            payload = data[pos:pos + n]
            pos += n
            stamp = genpy.Time(t_ns // 1_000_000_000, t_ns % 1_000_000_000)
            if first and not args.no_metadata:
                bag.write(ns + "/metadata", String(data=meta_text), stamp)
            first = False
            if kind == 1 and args.no_imu:
                continue
            for n in [ns] + ([args.also_ns.rstrip("/")] if args.also_ns else []):
                topic = n + ("/imu_packets" if kind == 1 else "/lidar_packets")
                bag.write(topic, PacketMsg(payload), stamp)


def checksum(header):
    s = sum(struct.unpack("!10H", header))
    s = (s & 0xFFFF) + (s >> 16)
    s = (s & 0xFFFF) + (s >> 16)
    return (~s) & 0xFFFF


def udp_record(payload, port):
    udp = struct.pack("!HHHH", port, port, 8 + len(payload), 0) + payload
    ip = bytearray(struct.pack("!BBHHHBBH4s4s", 0x45, 0, 20 + len(udp), 0, 0, 64, 17, 0,
                               bytes([10, 5, 5, 87]), bytes([10, 5, 5, 1])))
    ip[10:12] = struct.pack("!H", checksum(bytes(ip)))
    eth = b"\xff" * 6 + b"\x02" * 6 + b"\x08\x00"
    return eth + bytes(ip) + udp


def topcap(args):
    bag = rosbag.Bag(args.bag)
    topics = bag.get_type_and_topic_info().topics
    lidar = [t for t in topics if t.endswith("lidar_packets")]
    imu = [t for t in topics if t.endswith("imu_packets")]
    meta = [t for t in topics if t.endswith("metadata")]
    ports = {"lidar": 7502, "imu": 7503}
    for _, msg, _ in bag.read_messages(topics=meta):
        info = json.loads(msg.data)
        cfg = info.get("config_params", info)
        ports["lidar"] = cfg.get("udp_port_lidar") or 7502
        ports["imu"] = cfg.get("udp_port_imu") or 7503
        break
    out = io.BytesIO()
    out.write(struct.pack("<IHHiIII", 0xA1B23C4D, 2, 4, 0, 0, 262144, 1))  # ns, Ethernet
    for topic, msg, t in bag.read_messages(topics=lidar + imu, raw=True):
        payload = PacketMsg().deserialize(msg[1]).buf
        rec = udp_record(payload, ports["lidar"] if topic in lidar else ports["imu"])
        ns = t.to_nsec()
        out.write(struct.pack("<IIII", ns // 1_000_000_000, ns % 1_000_000_000, len(rec), len(rec)))
        out.write(rec)
    open(args.out, "wb").write(out.getvalue())


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    w = sub.add_parser("write")
    w.add_argument("packets")
    w.add_argument("metadata")
    w.add_argument("out")
    w.add_argument("--ns", default="/os_node")
    w.add_argument("--no-metadata", action="store_true")
    w.add_argument("--no-imu", action="store_true")
    w.add_argument("--also-ns")
    c = sub.add_parser("topcap")
    c.add_argument("bag")
    c.add_argument("out")
    args = p.parse_args()
    write(args) if args.cmd == "write" else topcap(args)


if __name__ == "__main__":
    sys.exit(main())
