#!/usr/bin/env python3
"""An independent ROS 2 / rmw_zenoh peer for `parol6 serve --ros2` (run by tests/ros2_zenoh.rs).

It uses the official Python Zenoh API (eclipse-zenoh) and its OWN CDR reader and writer (the
struct module) and its own REP-2011 type hashes, so nothing of ours checks ours. On loopback
only: it listens on tcp/127.0.0.1:PORT with multicast scouting off, and starts the binary with
`--ros2-connect tcp/127.0.0.1:PORT`. It checks:

- the liveliness tokens of rmw_zenoh (node `parol6`, its publishers and subscription, QoS);
- /joint_states and /tf: CDR, URDF joint names, attachments (sequence, time stamp, GID), and
  the transforms chained base_link -> L6 against `parol6 fk` at the published joints;
- /robot_description as a late joiner (transient local, through Zenoh's advanced subscriber,
  as rmw_zenoh's transient-local subscription is);
- with --remote: hostile trajectories (malformed CDR, NaN, wrong joint names, out of limits,
  times not increasing, a huge count) refused on /parol6/trajectory_result with no motion, then
  a valid one executed by the simulation (seen in the joint states it publishes back);
- without --remote: a valid trajectory refused (remote control off), no motion.

Prints one JSON line (what it saw) and exits 0, or prints the failure and exits 1.
"""
import argparse
import hashlib
import json
import math
import signal
import struct
import subprocess
import sys
import threading
import time

import zenoh
import zenoh.ext as ze

# --- REP-2011 type hashes, from the type descriptions -------------------------------------
NESTED, INT32, UINT32, DOUBLE, STRING, SEQ = 1, 6, 7, 11, 17, 144


def _f(name, tid, nested=""):
    return {"name": name, "type": {"type_id": tid, "capacity": 0, "string_capacity": 0, "nested_type_name": nested}}


TYPES = {
    "builtin_interfaces/msg/Time": [_f("sec", INT32), _f("nanosec", UINT32)],
    "builtin_interfaces/msg/Duration": [_f("sec", INT32), _f("nanosec", UINT32)],
    "std_msgs/msg/Header": [_f("stamp", NESTED, "builtin_interfaces/msg/Time"), _f("frame_id", STRING)],
    "std_msgs/msg/String": [_f("data", STRING)],
    "sensor_msgs/msg/JointState": [_f("header", NESTED, "std_msgs/msg/Header"), _f("name", STRING + SEQ),
                                   _f("position", DOUBLE + SEQ), _f("velocity", DOUBLE + SEQ), _f("effort", DOUBLE + SEQ)],
    "geometry_msgs/msg/Vector3": [_f("x", DOUBLE), _f("y", DOUBLE), _f("z", DOUBLE)],
    "geometry_msgs/msg/Quaternion": [_f("x", DOUBLE), _f("y", DOUBLE), _f("z", DOUBLE), _f("w", DOUBLE)],
    "geometry_msgs/msg/Transform": [_f("translation", NESTED, "geometry_msgs/msg/Vector3"),
                                    _f("rotation", NESTED, "geometry_msgs/msg/Quaternion")],
    "geometry_msgs/msg/TransformStamped": [_f("header", NESTED, "std_msgs/msg/Header"), _f("child_frame_id", STRING),
                                           _f("transform", NESTED, "geometry_msgs/msg/Transform")],
    "tf2_msgs/msg/TFMessage": [_f("transforms", NESTED + SEQ, "geometry_msgs/msg/TransformStamped")],
    "trajectory_msgs/msg/JointTrajectoryPoint": [_f("positions", DOUBLE + SEQ), _f("velocities", DOUBLE + SEQ),
                                                 _f("accelerations", DOUBLE + SEQ), _f("effort", DOUBLE + SEQ),
                                                 _f("time_from_start", NESTED, "builtin_interfaces/msg/Duration")],
    "trajectory_msgs/msg/JointTrajectory": [_f("header", NESTED, "std_msgs/msg/Header"), _f("joint_names", STRING + SEQ),
                                            _f("points", NESTED + SEQ, "trajectory_msgs/msg/JointTrajectoryPoint")],
}


def _refs(name, acc):
    for field in TYPES[name]:
        nested = field["type"]["nested_type_name"]
        if nested and nested not in acc:
            acc.add(nested)
            _refs(nested, acc)
    return acc


def rihs01(name):
    desc = {"type_description": {"type_name": name, "fields": TYPES[name]},
            "referenced_type_descriptions": [{"type_name": r, "fields": TYPES[r]} for r in sorted(_refs(name, set()))]}
    text = json.dumps(desc, ensure_ascii=True, allow_nan=False, indent=None, separators=(", ", ": "), sort_keys=False)
    return "RIHS01_" + hashlib.sha256(text.encode()).hexdigest()


def dds(name):
    pkg, kind, msg = name.split("/")
    return f"{pkg}::{kind}::dds_::{msg}_"


def key(topic, name, domain=0):
    return f"{domain}/{topic.strip('/')}/{dds(name)}/{rihs01(name)}"


# --- CDR -----------------------------------------------------------------------------------
class Reader:
    def __init__(self, payload):
        if len(payload) < 4 or payload[0] != 0 or payload[1] not in (0, 1):
            raise ValueError(f"not a plain CDR payload: {payload[:4]!r}")
        self.e = "<" if payload[1] == 1 else ">"
        self.b, self.o = payload[4:], 0

    def _take(self, fmt, size):
        self.o += (-self.o) % size
        (v,) = struct.unpack_from(self.e + fmt, self.b, self.o)
        self.o += size
        return v

    def u32(self):
        return self._take("I", 4)

    def i32(self):
        return self._take("i", 4)

    def f64(self):
        return self._take("d", 8)

    def string(self):
        n = self.u32()
        raw = self.b[self.o:self.o + n]
        self.o += n
        assert raw.endswith(b"\0"), raw
        return raw[:-1].decode()

    def seq(self, read):
        return [read() for _ in range(self.u32())]

    def header(self):
        return {"sec": self.i32(), "nanosec": self.u32(), "frame_id": self.string()}


def joint_state(payload):
    r = Reader(payload)
    return {"header": r.header(), "name": r.seq(r.string), "position": r.seq(r.f64),
            "velocity": r.seq(r.f64), "effort": r.seq(r.f64)}


def tf_message(payload):
    r = Reader(payload)
    out = []
    for _ in range(r.u32()):
        h = r.header()
        child = r.string()
        t = [r.f64() for _ in range(3)]
        q = [r.f64() for _ in range(4)]
        out.append({"parent": h["frame_id"], "child": child, "t": t, "q": q, "stamp": (h["sec"], h["nanosec"])})
    return out


def string_msg(payload):
    return Reader(payload).string()


class Writer:
    def __init__(self):
        self.b = bytearray()

    def _put(self, fmt, size, v):
        self.b += bytes((-len(self.b)) % size)
        self.b += struct.pack("<" + fmt, v)

    def u32(self, v):
        self._put("I", 4, v)

    def i32(self, v):
        self._put("i", 4, v)

    def f64(self, v):
        self._put("d", 8, v)

    def string(self, s):
        data = s.encode() + b"\0"
        self.u32(len(data))
        self.b += data

    def payload(self):
        return b"\x00\x01\x00\x00" + bytes(self.b)


def trajectory(points, names=("J1", "J2", "J3", "J4", "J5", "J6"), count=None):
    w = Writer()
    w.i32(0)
    w.u32(0)
    w.string("base_link")
    w.u32(len(names))
    for n in names:
        w.string(n)
    w.u32(len(points) if count is None else count)
    for q, t in points:
        w.u32(len(q))
        for v in q:
            w.f64(v)
        for _ in range(3):  # velocities, accelerations, effort: empty
            w.u32(0)
        w.i32(int(t))
        w.u32(int(round((t - int(t)) * 1e9)))
    return w.payload()


# --- quaternions for chaining /tf ---------------------------------------------------------
def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def qrot(q, v):
    p = qmul(qmul(q, [v[0], v[1], v[2], 0.0]), [-q[0], -q[1], -q[2], q[3]])
    return p[:3]


def chain(tfs, root="base_link", tip="L6"):
    by_parent = {t["parent"]: t for t in tfs}
    pos, rot, frame, seen = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0], root, []
    while frame != tip:
        t = by_parent[frame]
        pos = [p + d for p, d in zip(pos, qrot(rot, t["t"]))]
        rot = qmul(rot, t["q"])
        frame = t["child"]
        seen.append(frame)
    return pos, rot, seen


class Failure(Exception):
    pass


def check(cond, what):
    if not cond:
        raise Failure(what)


def wait_for(pred, timeout_s, what):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        v = pred()
        if v:
            return v
        time.sleep(0.02)
    raise Failure(f"timed out after {timeout_s} s waiting for {what}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", required=True)
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--remote", action="store_true")
    args = ap.parse_args()

    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("listen/endpoints", json.dumps([f"tcp/127.0.0.1:{args.port}"]))
    conf.insert_json5("connect/endpoints", "[]")
    conf.insert_json5("scouting/multicast/enabled", "false")
    session = zenoh.open(conf)

    lock = threading.Lock()
    got = {"js": [], "tf": [], "results": [], "attachments": []}

    def on_js(sample):
        msg = joint_state(bytes(sample.payload.to_bytes()))
        att = sample.attachment
        with lock:
            got["js"].append(msg)
            got["attachments"].append(ze.z_deserialize(tuple[ze.Int64, ze.Int64, bytes], att) if att else None)

    def on_tf(sample):
        msg = tf_message(bytes(sample.payload.to_bytes()))
        with lock:
            got["tf"].append(msg)

    def on_result(sample):
        msg = json.loads(string_msg(bytes(sample.payload.to_bytes())))
        with lock:
            got["results"].append(msg)

    subs = [
        session.declare_subscriber(key("/joint_states", "sensor_msgs/msg/JointState"), on_js),
        session.declare_subscriber(key("/tf", "tf2_msgs/msg/TFMessage"), on_tf),
        session.declare_subscriber(key("/parol6/trajectory_result", "std_msgs/msg/String"), on_result),
    ]
    cmd = [args.exe, "serve", "--ros2", "--ros2-connect", f"tcp/127.0.0.1:{args.port}", "--seconds", "90"]
    if args.remote:
        cmd.append("--allow-remote-control")
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    report = {"command": " ".join(cmd[1:])}
    try:
        first = json.loads(proc.stdout.readline() or "null")
        check(first and "ros2" in first.get("listening", {}), f"the first line names the ros2 server: {first}")
        report["listening"] = first["listening"]["ros2"]
        wait_for(lambda: len(got["js"]) >= 20 and len(got["tf"]) >= 5, 20, "joint states and transforms")

        # liveliness tokens
        tokens = [str(r.ok.key_expr) for r in session.liveliness().get("@ros2_lv/0/**", timeout=5.0) if r.ok]
        mine = [t for t in tokens if t.split("/")[8:9] == ["parol6"]]
        qos_default, qos_latched = "::,10:,:,:,,", ":1:,1:,:,:,,"
        want = [
            ("NN", None, None, None),
            ("MP", "%joint_states", "sensor_msgs/msg/JointState", qos_default),
            ("MP", "%tf", "tf2_msgs/msg/TFMessage", "::,100:,:,:,,"),
            ("MP", "%robot_description", "std_msgs/msg/String", qos_latched),
            ("MP", "%parol6%trajectory_result", "std_msgs/msg/String", qos_default),
            ("MS", "%parol6%joint_trajectory", "trajectory_msgs/msg/JointTrajectory", qos_default),
        ]
        for kind, topic, type_name, qos in want:
            found = [t for t in mine if t.split("/")[5] == kind and (topic is None or t.split("/")[9] == topic)]
            check(len(found) == 1, f"one {kind} token for {topic}: {mine}")
            parts = found[0].split("/")
            check(parts[6:9] == ["%", "%", "parol6"], f"enclave, namespace and node name: {found[0]}")
            if topic:
                check(parts[10:13] == [dds(type_name), rihs01(type_name), qos], f"type, hash, QoS of {found[0]}")
        report["tokens"] = len(mine)

        # joint states: names, attachments
        with lock:
            js, atts = list(got["js"]), list(got["attachments"])
        check(all(m["name"] == ["J1", "J2", "J3", "J4", "J5", "J6"] for m in js), "URDF joint names")
        check(all(a is not None for a in atts), "every sample has an attachment")
        seqs = [a[0] for a in atts]
        check(all(b == a + 1 for a, b in zip(seqs, seqs[1:])), f"sequence numbers count up by one: {seqs[:10]}")
        check(len({a[2] for a in atts}) == 1 and len(atts[0][2]) == 16, "one 16-byte GID")
        check(abs(atts[-1][1] / 1e9 - time.time()) < 5.0, "source time stamps are now")
        check(abs(js[-1]["header"]["sec"] - time.time()) < 5.0, "header stamps are now")
        report["joint_states"] = len(js)

        # /tf chained against `parol6 fk` at the published joints (the arm is at rest)
        with lock:
            tfs, q = got["tf"][-1], got["js"][-1]["position"]
        pos, rot, frames = chain(tfs)
        check(frames == ["L1", "L2", "L3", "L4", "L5", "L6"], f"base_link -> L6 through every link: {frames}")
        joints = ",".join(repr(v) for v in q)
        fk = json.loads(subprocess.run([args.exe, "fk", "--tool", "none", "--joints", joints], capture_output=True,
                                       text=True, check=True).stdout)
        err_m = math.dist(pos, fk["tcp"]["position_m"])
        w, x, y, z = fk["tcp"]["quaternion_wxyz"]
        dot = abs(rot[0] * x + rot[1] * y + rot[2] * z + rot[3] * w)
        check(err_m < 1e-6 and dot > 1 - 1e-9, f"/tf chain {pos} {rot} vs fk {fk['tcp']}")
        report["tf_vs_fk_error_m"] = err_m

        # /robot_description, joining late (transient local)
        urdf = []
        adv = ze.declare_advanced_subscriber(session, key("/robot_description", "std_msgs/msg/String"),
                                             lambda s: urdf.append(string_msg(bytes(s.payload.to_bytes()))),
                                             history=ze.HistoryConfig(detect_late_publishers=True))
        wait_for(lambda: urdf, 10, "the URDF on /robot_description (late joiner)")
        check("<robot" in urdf[0] and 'name="J6"' in urdf[0], "/robot_description is the URDF")
        report["robot_description_bytes"] = len(urdf[0])
        adv.undeclare()

        traj_key = key("/parol6/joint_trajectory", "trajectory_msgs/msg/JointTrajectory")
        seq = [0]

        def send(payload):
            seq[0] += 1
            att = ze.z_serialize((ze.Int64(seq[0]), ze.Int64(time.time_ns()), bytes(range(16))))
            session.put(traj_key, payload, attachment=att)
            n = seq[0]
            return wait_for(lambda: [r for r in list(got["results"]) if r["id"] == n and r["state"] != "running"]
                            or None, 20, f"the result of trajectory {n}")[0]

        start = list(q)
        moved = [start[0] + 0.2] + start[1:]
        valid = trajectory([(start, 0.0), (moved, 1.0), (start, 2.0)])
        n_before = len(got["js"])
        if args.remote:
            nan = list(moved)
            nan[2] = float("nan")
            far = list(start)
            far[1] = 3.0
            hostile = [
                ("malformed CDR", b"\x00\x01\x00\x00\xff\xff", "malformed JointTrajectory"),
                ("huge count", trajectory([], count=0xFFFFFFFF), "malformed JointTrajectory"),
                ("NaN", trajectory([(start, 0.0), (nan, 1.0)]), "not a finite number"),
                ("wrong joint names", trajectory([(moved, 1.0)], names=("a", "b", "c", "d", "e", "f")), "joint_names"),
                ("out of limits", trajectory([(start, 0.0), (far, 5.0)]), "limit"),
                ("times not increasing", trajectory([(moved, 1.0), (start, 1.0)]), "is not after the previous point"),
            ]
            refusals = {}
            for name, payload, needle in hostile:
                r = send(payload)
                check(r["state"] == "refused" and needle in r["reason"], f"{name} refused naming {needle!r}: {r}")
                refusals[name] = r["reason"]
            with lock:
                during = got["js"][n_before:]
            check(all(max(abs(a - b) for a, b in zip(m["position"], start)) < 1e-4 for m in during),
                  "no motion while the hostile trajectories were refused")
            report["refusals"] = refusals
            r = send(valid)
            check(r["state"] == "done", f"the valid trajectory ran: {r}")
            with lock:
                run = got["js"][n_before:]
            peak = max(m["position"][0] for m in run) - start[0]
            end = run[-1]["position"][0] - start[0]
            check(0.19 < peak < 0.21, f"J1 went +0.2 rad and back: peak {peak}")
            check(abs(end) < 0.005, f"J1 is back at the start: {end}")
            report["executed_peak_rad"] = peak
            report["executed_end_rad"] = end
        else:
            r = send(valid)
            check(r["state"] == "refused" and "remote control is off" in r["reason"], f"refused: {r}")
            time.sleep(0.5)
            with lock:
                during = got["js"][n_before:]
            check(all(max(abs(a - b) for a, b in zip(m["position"], start)) < 1e-4 for m in during),
                  "no motion without remote control")
            report["refusal"] = r["reason"]
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
        check(proc.returncode == 130, f"exit 130 after SIGINT, got {proc.returncode}: {err}")
        summary = json.loads(out.strip().splitlines()[-1])
        ros2 = summary["servers"]["ros2"]
        report["summary"] = {"network_commands": summary["network_commands"],
                             "network_commands_refused": summary["network_commands_refused"], "ros2": ros2}
        expected = 7 if args.remote else 1
        check(summary["network_commands"] == expected, f"{expected} network commands logged: {summary}")
        check(ros2["trajectories_refused"] == expected - (1 if args.remote else 0), f"refusals counted: {ros2}")
        print(json.dumps({"ok": True, **report}))
        return 0
    except Failure as e:
        print(json.dumps({"ok": False, "failure": str(e), **report}))
        return 1
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for s in subs:
            s.undeclare()
        session.close()


if __name__ == "__main__":
    sys.exit(main())
