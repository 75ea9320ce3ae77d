"""Child programs of bench/bench_peers.py: one method on one problem per process, so that
each process's peak memory belongs to one method."""
