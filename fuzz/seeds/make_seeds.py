#!/usr/bin/env python3
"""Writes the hand-made fuzz seeds into fuzz/seeds/<target>/ (run from the repository root).

Seeds are our own text and frames (the embedded PAROL6 URDF is copied from assets/); the
reference pack's official URDFs are never copied here.
"""
import os
import shutil
import struct

ROOT = os.path.dirname(os.path.abspath(__file__))


def i24(v):
    return (v & 0xFFFFFF).to_bytes(3, "big")


def command(code, positions=(0,) * 6, speeds=(0,) * 6, io=0, knob=0, gripper=(0, 0, 0, 0, 0, 0), length=52):
    payload = b"".join(i24(p) for p in positions) + b"".join(i24(s) for s in speeds)
    payload += bytes([code, 0x3F, io, knob])
    payload += struct.pack(">hhhBBB", *gripper)
    payload += bytes([0xE4])
    body = payload + bytes(max(0, length - 2 - len(payload)))
    body = body[: length - 2] + b"\x01\x02"
    return b"\xff\xff\xff" + bytes([length]) + body


def write(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


IDLE, HOME, ENABLE, DISABLE, CLEAR, JOG, MOVE = 255, 100, 101, 102, 103, 123, 156
STANDBY = (10240, -32000, 57905, 0, 0, 32000)

# --- command_emulator: host -> controller streams -------------------------------------------
write("command_emulator", "enable_home_idle", command(ENABLE, knob=5) + command(HOME, knob=0x3F) + command(IDLE, knob=0x3F) * 4)
write("command_emulator", "jog_then_disable", command(ENABLE) + command(JOG, speeds=(1000, -2000, 50000, -60000, 0, 7), knob=10) + command(DISABLE, knob=10) + command(JOG, speeds=(1000,) * 6, knob=10))
write("command_emulator", "move_stream", b"".join(command(MOVE, positions=tuple(p + 50 * k for p in STANDBY), speeds=(500,) * 6, knob=3) for k in range(5)))
write("command_emulator", "outputs_gripper_estop", command(IDLE, io=0x30, knob=0x80, gripper=(120, 50, 300, 0x80, 0, 0)) + command(IDLE, io=0x20, knob=0x40, gripper=(0, 0, 0, 0, 1, 0)))
write("command_emulator", "unknown_codes_and_noise", b"\x00\xff\xff" + command(69, knob=2) + command(200) + b"\xff\xff\xff\x00" + command(CLEAR, length=60) + command(IDLE, length=10) + b"\xff\xff\xff\x05abc\x01\x02")
write("command_emulator", "extremes", command(MOVE, positions=(8388607, -8388608, 0, 1, -1, 4096), speeds=(-8388608, 8388607, 0, 0, 0, 0), knob=0x3F) + command(IDLE, speeds=(8388607,) * 6, knob=0x3F))

# --- status_parser: controller -> host bytes (seeded with command frames and status-like frames)
status = b"\xff\xff\xff\x38" + bytes(range(52)) + b"\xd4\x01\x02"
write("status_parser", "status_like", status * 2)
write("status_parser", "noise_then_status", b"\x01\x02\xff\xff" + status[:30] + status)

# --- urdf_loader: our own small URDFs, valid and broken ---------------------------------------
os.makedirs(os.path.join(ROOT, "urdf_loader"), exist_ok=True)
shutil.copy(os.path.join(ROOT, "..", "..", "assets", "parol6", "parol6.urdf"), os.path.join(ROOT, "urdf_loader", "parol6_embedded.urdf"))


def link(name, body=""):
    return f'<link name="{name}">{body}</link>'


def joint(name, kind, parent, child, xyz="0 0 0.1", rpy="0 0 0", axis="0 0 1", limit='<limit lower="-1" upper="1" effort="1" velocity="1"/>'):
    return f'<joint name="{name}" type="{kind}"><origin xyz="{xyz}" rpy="{rpy}"/><parent link="{parent}"/><child link="{child}"/><axis xyz="{axis}"/>{limit}</joint>'


inertial = '<inertial><origin xyz="0 0 0.05"/><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>'
shapes = [
    '<box size="0.05 0.05 0.1"/>',
    '<cylinder radius="0.03" length="0.1"/>',
    '<sphere radius="0.04"/>',
    '<capsule radius="0.02" length="0.08"/>',
]


def geo(shape, z="0.05"):
    return f'<visual><origin xyz="0 0 {z}"/><geometry>{shape}</geometry><material name="m"><color rgba="1 0 0 1"/></material></visual><collision><origin xyz="0 0 {z}"/><geometry>{shape}</geometry></collision>'


one = f'<robot name="one">{link("base", inertial + geo(shapes[0]))}{link("tip", inertial + geo(shapes[2]))}{joint("j1", "revolute", "base", "tip")}</robot>'
write("urdf_loader", "one_joint.urdf", one)

six_links = "".join(link(f"l{i}", inertial + geo(shapes[i % 4])) for i in range(7))
six_joints = "".join(
    joint(f"j{i}", "revolute", f"l{i - 1}", f"l{i}", xyz=f"0 {0.02 * (i % 2)} 0.12", rpy=f"{1.5708 * (i % 2)} 0 0", axis="0 0 1" if i % 2 else "0 1 0")
    for i in range(1, 7)
)
write("urdf_loader", "six_dof_primitives.urdf", f'<?xml version="1.0"?>\n<robot name="six">{six_links}{six_joints}</robot>')

mixed = (
    '<robot name="mixed" version="1.1">'
    + link("world")
    + link("base", geo(shapes[1]))
    + link("slider", inertial + geo(shapes[0]))
    + link("spinner", inertial + geo(shapes[3]))
    + link("flange")
    + joint("fix", "fixed", "world", "base", limit="")
    + '<joint name="p" type="prismatic"><origin xyz="0 0 0.1" quat_xyzw="0 0 0.7071068 0.7071068"/><parent link="base"/><child link="slider"/><axis xyz="1 0 0"/><limit lower="0" upper="0.3" effort="10" velocity="0.2"/></joint>'
    + joint("c", "continuous", "slider", "spinner", axis="0 0 1", limit="")
    + joint("tipfix", "fixed", "spinner", "flange", xyz="0 0 0.05", limit="")
    + '<disable_collisions link1="base" link2="spinner" reason="Never"/>'
    + "</robot>"
)
write("urdf_loader", "prismatic_continuous_fixed.urdf", mixed)
MESH = '<mesh filename="package://nothere/meshes/a.stl" scale="0.001 0.001 0.001"/>'
write("urdf_loader", "mesh_missing.urdf", f'<robot name="m">{link("a", geo(MESH))}{link("b")}{joint("j", "revolute", "a", "b")}</robot>')
write("urdf_loader", "xml_constructs.urdf", '<?xml version="1.0"?>\n<!DOCTYPE robot [ <!ENTITY x "y"> ]>\n<robot name="q&lt;&quot;">\n<!-- <a><b> -->\n' + link("a", "<![CDATA[<x>]]>") + link("b") + joint("j", "revolute", "a", "b") + "<?pi data?></robot>")
write("urdf_loader", "broken_cycle.urdf", f'<robot name="c">{link("a")}{link("b")}{joint("j1", "revolute", "a", "b")}{joint("j2", "revolute", "b", "a")}</robot>')
write("urdf_loader", "broken_missing_link.urdf", f'<robot name="m">{link("a")}{joint("j1", "revolute", "a", "ghost")}</robot>')
BAD_LIMIT = '<limit lower="2" upper="-2" effort="1" velocity="1"/>'
write("urdf_loader", "broken_limits_axis.urdf", f'<robot name="l">{link("a")}{link("b")}{link("c")}{joint("j1", "revolute", "a", "b", limit=BAD_LIMIT)}{joint("j2", "revolute", "b", "c", axis="0 0 0")}</robot>')
write("urdf_loader", "broken_truncated.urdf", one[: len(one) // 2])
write("urdf_loader", "nested_too_deep.urdf", '<robot name="d">' + "<a>" * 70 + "</a>" * 70 + "</robot>")
write("urdf_loader", "not_xml.txt", "this is not a robot < > & \x00")

# --- atomic_writer: flags, ENOSPC byte (u16 BE), longest write, encoder write size, repeat, split, old + new ---
def atomic(flags, enospc=0, max_write=0, chunk=64, repeat=0, old=b"old program\n", new=b"G21 G90\nG1 X0 Y250 Z300\n"):
    return bytes([flags]) + enospc.to_bytes(2, "big") + bytes([max_write, chunk, repeat, len(old)]) + old + new


write("atomic_writer", "plain_replace", atomic(0x01))
write("atomic_writer", "new_file", atomic(0x00))
write("atomic_writer", "full_disk_at_byte_5", atomic(0x11, enospc=5))
write("atomic_writer", "full_disk_past_the_buffer", atomic(0x11, enospc=9000, repeat=7, new=bytes(range(256)) * 8))
write("atomic_writer", "short_writes", atomic(0x21, max_write=3, repeat=3))
write("atomic_writer", "short_writes_then_full", atomic(0x31, enospc=40, max_write=7))
write("atomic_writer", "fsync_fails", atomic(0x03))
write("atomic_writer", "rename_fails", atomic(0x05))
write("atomic_writer", "encoder_fails", atomic(0x09, chunk=1))
write("atomic_writer", "everything_fails_no_old", atomic(0x3E, enospc=1, max_write=1))
write("atomic_writer", "empty_new_content", atomic(0x11, enospc=0, new=b""))

# --- ros2_cdr: ROS 2 CDR payloads (little-endian header 00 01 00 00, XCDR1 body) ---------------
class Cdr:
    def __init__(self, big=False):
        self.e = ">" if big else "<"
        self.b = bytearray()

    def align(self, n):
        while len(self.b) % n:
            self.b.append(0)

    def u32(self, v):
        self.align(4)
        self.b += struct.pack(self.e + "I", v)
        return self

    def i32(self, v):
        self.align(4)
        self.b += struct.pack(self.e + "i", v)
        return self

    def f64(self, v):
        self.align(8)
        self.b += struct.pack(self.e + "d", v)
        return self

    def string(self, s):
        data = s.encode() + b"\0"
        self.u32(len(data))
        self.b += data
        return self

    def doubles(self, vs):
        self.u32(len(vs))
        for v in vs:
            self.f64(v)
        return self

    def payload(self):
        return (b"\x00\x00\x00\x00" if self.e == ">" else b"\x00\x01\x00\x00") + bytes(self.b)


STANDBY_DEG = (90.0, -90.0, 180.0, 0.0, 0.0, 180.0)
import math
STANDBY_RAD = [math.radians(d) for d in STANDBY_DEG]


def trajectory(points, names=("J1", "J2", "J3", "J4", "J5", "J6"), big=False):
    c = Cdr(big).i32(0).u32(0).string("base_link").u32(len(names))
    for n in names:
        c.string(n)
    c.u32(len(points))
    for q, v, t in points:
        c.doubles(q).doubles(v).doubles([]).doubles([])
        c.i32(int(t)).u32(int(round((t - int(t)) * 1e9)))
    return c.payload()


moved = [STANDBY_RAD[0] + 0.2] + STANDBY_RAD[1:]
write("ros2_cdr", "trajectory_valid", trajectory([(STANDBY_RAD, [], 0.0), (moved, [0.0] * 6, 1.0), (STANDBY_RAD, [], 2.0)]))
write("ros2_cdr", "trajectory_big_endian", trajectory([(STANDBY_RAD, [], 0.0), (moved, [], 1.5)], big=True))
write("ros2_cdr", "trajectory_reordered", trajectory([(list(reversed(moved)), [], 1.0)], names=("J6", "J5", "J4", "J3", "J2", "J1")))
write("ros2_cdr", "trajectory_nan", trajectory([(STANDBY_RAD[:2] + [float("nan")] + STANDBY_RAD[3:], [], 1.0)]))
write("ros2_cdr", "trajectory_out_of_limits", trajectory([([STANDBY_RAD[0], 3.0] + STANDBY_RAD[2:], [], 4.0)]))
write("ros2_cdr", "trajectory_not_monotonic", trajectory([(moved, [], 1.0), (STANDBY_RAD, [], 1.0)]))
write("ros2_cdr", "trajectory_wrong_names", trajectory([(moved, [], 1.0)], names=("a", "b", "c", "d", "e", "f")))
write("ros2_cdr", "trajectory_cut", trajectory([(moved, [], 1.0)])[:-7])
write("ros2_cdr", "trajectory_huge_count", Cdr().i32(0).u32(0).string("").u32(0xFFFFFFFF).payload())


def send_goal(points, names=("J1", "J2", "J3", "J4", "J5", "J6"), tolerance=(), multi_dof=False):
    """FollowJointTrajectory SendGoal request: UUID (16 bytes), then the goal field by field."""
    body = trajectory(points, names)[4:]
    c = Cdr()
    c.b += bytes(range(16)) + body
    c.i32(0).u32(0).string("").u32(1 if multi_dof else 0)
    if multi_dof:
        c.string("base")
    c.u32(0).u32(0).u32(0).u32(len(tolerance))
    for name, pos in tolerance:
        c.string(name).f64(pos).f64(0.0).f64(-1.0)
    return c.u32(0).i32(0).u32(0).payload()


write("ros2_cdr", "send_goal", send_goal([(STANDBY_RAD, [], 0.0), (moved, [], 1.0)], tolerance=[("J1", 0.01)]))
write("ros2_cdr", "send_goal_multi_dof", send_goal([(moved, [], 1.0)], multi_dof=True))
write("ros2_cdr", "send_goal_cut", send_goal([(moved, [], 1.0)])[:-9])


def feedback(goal_id, names, desired, actual):
    """FollowJointTrajectory_FeedbackMessage (Jazzy): UUID, header, joint_names, desired / actual /
    error points, multi_dof_joint_names and three empty multi-DOF points."""
    c = Cdr()
    c.b += goal_id
    c.i32(1).u32(2).string("").u32(len(names))
    for n in names:
        c.string(n)
    error = [d - a for d, a in zip(desired, actual)]
    for q, t in ((desired, 0.25), (actual, 0.25), (error, 0.0)):
        c.doubles(q).doubles([0.0] * len(q)).doubles([]).doubles([])
        c.i32(int(t)).u32(int(round((t - int(t)) * 1e9)))
    c.u32(0)
    for _ in range(3):
        c.u32(0).u32(0).u32(0).i32(0).u32(0)
    return c.payload()


write("ros2_cdr", "feedback", feedback(bytes(range(16)), ("J1", "J2", "J3", "J4", "J5", "J6"), moved, STANDBY_RAD))
write("ros2_cdr", "cancel_goal", Cdr().payload() + bytes(16) + bytes(8))
status = Cdr().u32(1)
status.b += bytes(range(16))
write("ros2_cdr", "goal_status_array", status.i32(1).u32(2).payload() + b"\x02")
js = Cdr().i32(1).u32(2).string("").u32(6)
for n in ("J1", "J2", "J3", "J4", "J5", "J6"):
    js.string(n)
js.doubles(STANDBY_RAD).doubles([0.0] * 6).doubles([])
write("ros2_cdr", "joint_state", js.payload())
tf = Cdr().u32(1).i32(1).u32(2).string("base_link").string("L1")
for v in (0.0, 0.0, 0.11, 0.0, 0.0, 0.0, 1.0):
    tf.f64(v)
write("ros2_cdr", "tf_message", tf.payload())
write("ros2_cdr", "string", Cdr().string("<robot name=\"parol6\"/>").payload())
write("ros2_cdr", "not_cdr", b"\x00\x07\x00\x00hello")
