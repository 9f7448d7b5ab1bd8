#!/usr/bin/env python3
"""An independent Foxglove WebSocket client for the tests (Python `websockets` only).

Speaks Foxglove's WebSocket protocol itself (subprotocol `foxglove.sdk.v1`, the current name of
`foxglove.websocket.v1`: the same messages; the `foxglove` crate's server answers only the new
name, so both are offered): reads `serverInfo` and `advertise`
(JSON text frames), sends `subscribe`, and decodes the binary message-data frames
(opcode 0x01, u32 subscription id, u64 log time ns, payload), all little-endian.

The offer can be replaced by the environment variable FOXGLOVE_SUBPROTOCOLS (comma-separated).

Modes:
  receive URL SECONDS [TOPICS]
                        subscribe to every channel (or those of the comma-separated TOPICS),
                        read for SECONDS, then print one JSON
                        object: the channels advertised, per-topic counts and time spans, the
                        /robot_description length, and pairs of (/joint_states positions, the
                        flange position chained from the /tf transforms of the same stamp).
  slow URL SECONDS      subscribe to every channel with a tiny receive buffer and read nothing
                        for SECONDS (a client that cannot keep up), then read until the first
                        jump in /joint_states `seq` (at most 8 s) and print what arrived: /joint_states messages and the gaps in their `seq` (the
                        messages the server dropped for this client).

The /tf chain is computed here with its own quaternion arithmetic, independent of the server.
"""

import asyncio
import json
import os
import socket
import struct
import sys
import time
from urllib.parse import urlparse

import websockets

# FOXGLOVE_SUBPROTOCOLS (comma-separated) replaces the offer, e.g. `foxglove.websocket.v1` alone
# as Lichtblick 1.x and `@foxglove/ws-protocol` 0.7 offer it.
SUBPROTOCOLS = [p for p in os.environ.get("FOXGLOVE_SUBPROTOCOLS", "foxglove.sdk.v1,foxglove.websocket.v1").split(",") if p]


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def rotate(q, v):
    x, y, z, w = quat_mul(quat_mul(q, (v[0], v[1], v[2], 0.0)), (-q[0], -q[1], -q[2], q[3]))
    return (x, y, z)


def chain(transforms, root, tip):
    """Pose of `tip` in `root` by following parent -> child transforms."""
    by_child = {t["child_frame_id"]: t for t in transforms}
    path = []
    frame = tip
    while frame != root:
        t = by_child.get(frame)
        if t is None:
            return None
        path.append(t)
        frame = t["parent_frame_id"]
    pos = (0.0, 0.0, 0.0)
    rot = (0.0, 0.0, 0.0, 1.0)
    for t in reversed(path):
        tr = t["translation"]
        r = t["rotation"]
        off = rotate(rot, (tr["x"], tr["y"], tr["z"]))
        pos = (pos[0] + off[0], pos[1] + off[1], pos[2] + off[2])
        rot = quat_mul(rot, (r["x"], r["y"], r["z"], r["w"]))
    return pos


async def handshake(ws):
    """serverInfo, then the advertisements (until a short quiet spell)."""
    info = None
    channels = {}
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline:
        try:
            frame = await asyncio.wait_for(ws.recv(), timeout=0.5 if channels else 5.0)
        except asyncio.TimeoutError:
            if channels:
                break
            continue
        if isinstance(frame, bytes):
            continue
        msg = json.loads(frame)
        if msg.get("op") == "serverInfo":
            info = msg
        elif msg.get("op") == "advertise":
            for c in msg["channels"]:
                channels[c["id"]] = c
    return info, channels


async def message_data(ws, seconds):
    """The server's Message Data frames (opcode 0x01) for `seconds`: (subscription id, log time, payload)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        try:
            frame = await asyncio.wait_for(ws.recv(), timeout=max(0.01, end - time.monotonic()))
        except asyncio.TimeoutError:
            return
        if isinstance(frame, bytes) and frame[0] == 0x01:
            sub_id, log_time = struct.unpack_from("<IQ", frame, 1)
            yield sub_id, log_time, frame[13:]


async def receive(url, seconds, topics=None):
    async with websockets.connect(url, subprotocols=SUBPROTOCOLS, max_size=None) as ws:
        if ws.subprotocol not in SUBPROTOCOLS:
            raise SystemExit(f"server chose subprotocol {ws.subprotocol!r}")
        info, channels = await handshake(ws)
        wanted = sorted(c for c in channels if topics is None or channels[c]["topic"] in topics)
        subs = [{"id": i + 1, "channelId": cid} for i, cid in enumerate(wanted)]
        topic_of = {s["id"]: channels[s["channelId"]]["topic"] for s in subs}
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))
        counts = {}
        first = {}
        last = {}
        description_len = None
        joints_by_stamp = {}
        tf_by_stamp = {}
        names = None
        async for sub_id, log_time, payload in message_data(ws, seconds):
            topic = topic_of.get(sub_id)
            counts[topic] = counts.get(topic, 0) + 1
            first.setdefault(topic, log_time)
            last[topic] = log_time
            msg = json.loads(payload)
            if topic == "/robot_description":
                description_len = len(msg["data"])
            elif topic == "/joint_states":
                stamp = msg["header"]["stamp"]
                names = msg["name"]
                joints_by_stamp[(stamp["sec"], stamp["nsec"])] = msg["position"]
            elif topic == "/tf":
                ts = msg["transforms"][0]["timestamp"]
                tf_by_stamp[(ts["sec"], ts["nsec"])] = msg["transforms"]
        pairs = []
        for stamp in sorted(tf_by_stamp):
            q = joints_by_stamp.get(stamp)
            if q is None:
                continue
            flange = chain(tf_by_stamp[stamp], "base_link", "L6")
            if flange is not None:
                pairs.append({"q": q, "flange_m": flange})
        # a spread of pairs over the run
        step = max(1, len(pairs) // 12)
        print(json.dumps({
            "server": (info or {}).get("name"),
            "subprotocol": ws.subprotocol,
            "advertised": [
                {k: c[k] for k in ("topic", "encoding", "schemaName", "schemaEncoding")}
                | {"schema_len": len(c.get("schema", ""))}
                for c in channels.values()
            ],
            "counts": counts,
            "span_s": {t: (last[t] - first[t]) * 1e-9 for t in counts},
            "robot_description_len": description_len,
            "joint_names": names,
            "pairs_total": len(pairs),
            "pairs": pairs[::step],
        }))


async def slow(url, seconds):
    parsed = urlparse(url)
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.connect((parsed.hostname, parsed.port))
    async with websockets.connect(
        url, sock=sock, subprotocols=SUBPROTOCOLS, max_size=None, close_timeout=1
    ) as ws:
        info, channels = await handshake(ws)
        subs = [{"id": i + 1, "channelId": cid} for i, cid in enumerate(sorted(channels))]
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))
        topic_of = {s["id"]: channels[s["channelId"]]["topic"] for s in subs}
        # read nothing: the socket's buffers fill, then the server's queue for this client
        ws.transport.pause_reading()
        await asyncio.sleep(seconds)
        ws.transport.resume_reading()
        seqs = []
        end = time.monotonic() + 8.0
        # what the socket buffers held comes first, in order; then the jump over what the
        # server dropped from this client's queue
        while time.monotonic() < end and not (len(seqs) >= 2 and seqs[-1] != seqs[-2] + 1):
            try:
                frame = await asyncio.wait_for(ws.recv(), timeout=max(0.01, end - time.monotonic()))
            except asyncio.TimeoutError:
                break
            if isinstance(frame, bytes) and frame[0] == 0x01:
                sub_id, _ = struct.unpack_from("<IQ", frame, 1)
                if topic_of.get(sub_id) == "/joint_states":
                    seqs.append(json.loads(frame[13:])["seq"])
        gaps = sum(1 for a, b in zip(seqs, seqs[1:]) if b != a + 1)
        print(json.dumps({"channels": len(channels), "joint_states": len(seqs), "seq_gaps": gaps}))


async def events(url, seconds):
    """Prints each `/events` message (foxglove.Log, JSON) as one JSON line as it arrives."""
    async with websockets.connect(url, subprotocols=SUBPROTOCOLS, max_size=None) as ws:
        _, channels = await handshake(ws)
        wanted = [cid for cid, c in channels.items() if c["topic"] == "/events"]
        if not wanted:
            raise SystemExit(f"no /events channel among {sorted(c['topic'] for c in channels.values())}")
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 1, "channelId": wanted[0]}]}))
        print(json.dumps({"subscribed": "/events"}), flush=True)
        async for sub_id, _, payload in message_data(ws, seconds):
            if sub_id == 1:
                msg = json.loads(payload)
                print(json.dumps({k: msg.get(k) for k in ("level", "name", "message")}), flush=True)


def main():
    mode, url, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3])
    if mode == "events":
        try:
            asyncio.run(events(url, seconds))
        except (KeyboardInterrupt, websockets.ConnectionClosed):
            pass
    elif mode == "receive":
        topics = sys.argv[4].split(",") if len(sys.argv) > 4 else None
        asyncio.run(receive(url, seconds, topics))
    elif mode == "slow":
        asyncio.run(slow(url, seconds))
    else:
        raise SystemExit(f"unknown mode {mode}")


if __name__ == "__main__":
    main()
