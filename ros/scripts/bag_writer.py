#!/usr/bin/env python3
"""Writes the messages sgslam_ros_play sends down its stdin to a ROS 1 bag.

Each message is a line "topic datatype md5sum secs nsecs length", then length
bytes of the serialized message; the line "END" closes the stream. The bag is
written to a new file TEMP_PREFIX<random> (created exclusively: a link planted
under a fixed name is never written through; the player passes the prefix of its
own temporary names, io/atomic_write.h, so a later writer of OUT removes the file
if both were killed) and renamed to OUT only after END, so a player that stopped early leaves no
bag under OUT's name, and no temporary file either.
"""
import os
import sys
import tempfile

import genpy
import rosbag
import roslib.message


def write(out, tmp, inp):
    types = {}
    count = 0
    with rosbag.Bag(tmp, "w") as bag:
        while True:
            line = inp.readline()
            if not line:
                raise RuntimeError(f"the player stopped after {count} messages, before the end")
            if line == b"END\n":
                return count
            topic, datatype, md5sum, secs, nsecs, length = line.decode().split()
            data = inp.read(int(length))
            if len(data) != int(length):
                raise RuntimeError(f"message {count} on {topic} cut short")
            if datatype not in types:
                types[datatype] = roslib.message.get_message_class(datatype)
                if types[datatype] is None:
                    raise RuntimeError(f"no Python message class for {datatype}")
            bag.write(topic, (datatype, data, md5sum, None, types[datatype]), genpy.Time(int(secs), int(nsecs)),
                      raw=True)
            count += 1


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: bag_writer.py OUT.bag TEMP_PREFIX < messages")
    out, prefix = sys.argv[1], sys.argv[2]
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=os.path.basename(prefix), dir=os.path.dirname(prefix) or ".")
        os.close(fd)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # as an ordinary new file (mkstemp makes it 0600)
        write(out, tmp, sys.stdin.buffer)
        os.replace(tmp, out)
    except Exception as e:  # noqa: BLE001 (any failure: no bag, no temporary file, the reason)
        if tmp and os.path.exists(tmp):
            os.remove(tmp)
        sys.exit(f"bag_writer.py: {e}; {out} not written")


if __name__ == "__main__":
    main()
