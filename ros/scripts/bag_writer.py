#!/usr/bin/env python3
"""Writes the messages sgslam_ros_play sends down its stdin to a ROS 1 bag.

Each message is a line "topic datatype md5sum secs nsecs length", then length
bytes of the serialized message. The bag is written to OUT.tmp and renamed to OUT
when every message is in, so a failed run leaves no torn bag under OUT's name.
"""
import os
import sys

import genpy
import rosbag
import roslib.message


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: bag_writer.py OUT.bag < messages")
    out = sys.argv[1]
    tmp = out + ".tmp"
    types = {}
    inp = sys.stdin.buffer
    count = 0
    with rosbag.Bag(tmp, "w") as bag:
        while True:
            line = inp.readline()
            if not line:
                break
            topic, datatype, md5sum, secs, nsecs, length = line.decode().split()
            data = inp.read(int(length))
            if len(data) != int(length):
                sys.exit(f"bag_writer.py: message {count} on {topic} cut short; {out} not written")
            if datatype not in types:
                types[datatype] = roslib.message.get_message_class(datatype)
                if types[datatype] is None:
                    sys.exit(f"bag_writer.py: no Python message class for {datatype}")
            pytype = types[datatype]
            bag.write(topic, (datatype, data, md5sum, None, pytype), genpy.Time(int(secs), int(nsecs)), raw=True)
            count += 1
    os.replace(tmp, out)


if __name__ == "__main__":
    main()
