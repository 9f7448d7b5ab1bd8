#!/usr/bin/env python3
"""Reads an MCAP file with the official Python `mcap` reader (CRCs checked) and prints one JSON
summary: schemas and encodings per topic, message counts, the metadata, and the first and last
/joint_states message. Written for PAROL6 Studio's tests; it knows nothing of our writer."""
import json
import sys

from mcap.reader import make_reader


def main(path):
    topics = {}
    first = last = None
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
        for schema, channel, message in reader.iter_messages():
            t = topics.setdefault(
                channel.topic,
                {
                    "schema": schema.name if schema else None,
                    "schema_encoding": schema.encoding if schema else None,
                    "message_encoding": channel.message_encoding,
                    "count": 0,
                    "log_time_monotonic": True,
                    "last_log_time": 0,
                },
            )
            if message.log_time < t["last_log_time"]:
                t["log_time_monotonic"] = False
            t["last_log_time"] = message.log_time
            t["count"] += 1
            if channel.topic == "/joint_states":
                decoded = json.loads(message.data)
                first = first or decoded
                last = decoded
    print(
        json.dumps(
            {
                "topics": topics,
                "metadata": metadata,
                "chunks": len(summary.chunk_indexes) if summary else None,
                "first_joint_state": first,
                "last_joint_state": last,
            }
        )
    )


if __name__ == "__main__":
    main(sys.argv[1])
