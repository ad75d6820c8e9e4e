"""e2e_common.py — what the Python end-to-end tests share.

Only facts about the build under test live here: the tests themselves keep
their own cases and checks.
"""
import os


def sanitized(bin_dir, program):
    """Whether `program` in bin_dir was built with ASan (it links libasan):
    its shadow memory needs terabytes of address space, so an address-space
    cap (prlimit --as, RLIMIT_AS) cannot be used on it."""
    try:
        with open(os.path.join(bin_dir, program), "rb") as f:
            return b"libasan" in f.read()
    except OSError:
        return False
