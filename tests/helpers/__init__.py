"""Test helpers shared by the transport, node and recording tests (real processes, real Zenoh)."""
