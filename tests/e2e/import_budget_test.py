#!/usr/bin/env python3
"""import_budget_test.py — every model import held to the budget and to a time (#42 B5),
and --compare's reference and work counted in the run's one budget (B6).

    import_budget_test.py BIN_DIR WORK_DIR

Each case runs hw3_shading_ref (build/bin) on a hostile model or scene,
generated here (no big file is committed), and checks:
  - the exit status (2 and a located message for a refused file; 0 for a
    legal one),
  - a piece of the message on stderr,
  - the process tree's peak resident memory (the program and its import
    child, from wait4) within 1 GiB, and its processor time within 20 s
    (so the test passes on a busy machine; the clock, at 120 s, only ends
    a run that waits);
  - no AddressSanitizer / UBSan report.
The cases (issue 42, B5):
  - 300,000 'l' polylines (the estimate lets them through, assimp takes
    453 MB) under --memory-limit 256: stopped by the import child's
    RLIMIT_AS (not under ASan);
  - 100,000 'g' groups (assimp: 342 MB) refused up front by the estimate
    under --memory-limit 256 (3.4 KB a group); 20,000 render;
  - a 90-byte OBJ naming a .mtl of 100,000 materials (assimp: 3.5 GB): refused
    up front by the estimate, also under --memory-limit 256;
  - an OBJ switching material on each of 100,000 faces, and one of 100,000
    'o' objects (assimp's OBJ reader is quadratic in both): refused at once;
  - a scene naming one small OBJ in 4,096 objects: imported once, done;
  - a PLY cut inside its header, or with end_header misspelt: refused at once
    (assimp waited out its whole 60 s limit);
  - mtllib outside the model's folder (.., an absolute path, a link): refused;
  - out-of-range vt / vn indices: refused, naming the line;
  - a scene's imports together past RAS_MESH_IMPORT_TOTAL_SECONDS: an error
    naming the file it was on;
  - hw2_rasterize --compare at 8192x8192 (the largest legal size): refused up
    front, exit 2, with the default budget and with --memory-limit 4096;
  - the program killed (SIGTERM, SIGKILL) while its import child works: the
    child is killed too (the test is the orphan's subreaper, so it sees how
    the child ended: SIGKILL, from PR_SET_PDEATHSIG, not a later exit).
Exit status 0 when every check passes; each failure is printed.
"""
import ctypes
import json
import os
import resource
import shutil
import signal
import struct
import subprocess
import sys

import e2e_common
import time
import zlib

BIN, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])


SANITIZED = e2e_common.sanitized(BIN, "hw3_shading_ref")
H3 = os.path.join(BIN, "hw3_shading_ref")
# Every case: 20 s of processor time (the program and its import child) and
# 1 GiB resident, the bounds. Processor time, not the clock, so that
# the test passes on a busy machine; the clock is only a backstop for a run
# that waits without working, at six times the bound.
SECONDS, PEAK_KB = 20, 1 << 20
WALL_BACKSTOP = 6 * SECONDS
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []


def path(name):
    return os.path.join(WORK, name)


def write(name, data):
    os.makedirs(os.path.dirname(path(name)), exist_ok=True)
    with open(path(name), "w") as f:
        f.write(data)
    return path(name)


def cpu_of_children():
    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


def run(args, env_extra=None, timeout=WALL_BACKSTOP, program=H3):
    """Runs `program`; (exit status, stderr, processor seconds, peak KB of the
    tree). The processor time is the program's and every child it waited for
    (its import child), as RUSAGE_CHILDREN sums them."""
    env = dict(os.environ)
    for k in ("DISPLAY", "WAYLAND_DISPLAY", "RAS_MEMORY_LIMIT_MB", "RAS_MESH_IMPORT_SECONDS",
              "RAS_MESH_IMPORT_TOTAL_SECONDS"):
        env.pop(k, None)
    env.update(env_extra or {})
    cpu_before = cpu_of_children()
    # A process group of its own: a late case is ended whole, an import
    # child that outlived the program included (it holds stderr open).
    p = subprocess.Popen([program] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         env=env, cwd=WORK, start_new_session=True)
    try:
        _, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return "timeout", "", cpu_of_children() - cpu_before, 0
    # ru_maxrss of RUSAGE_CHILDREN: the largest of every process waited for
    # so far, the import children (waited for by the program) included.
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return p.returncode, err.decode(errors="replace"), cpu_of_children() - cpu_before, peak


peak_before = 0


def case(name, args, status, message, env=None, program=H3):
    global peak_before
    code, err, cpu, peak = run(args, env, program=program)
    problems = []
    if code != status:
        problems.append(f"exit {code}, expected {status}")
    if message not in err:
        problems.append(f"stderr lacks {message!r}")
    if code == "timeout":
        problems.append(f"still running after {WALL_BACKSTOP} s on the clock")
    if cpu > SECONDS:
        problems.append(f"took {cpu:.1f} s of processor time, expected at most {SECONDS} s")
    # RUSAGE_CHILDREN only grows: a new maximum belongs to this case.
    if peak > PEAK_KB and peak > peak_before:
        problems.append(f"peak resident memory {peak >> 10} MiB, expected at most "
                        f"{PEAK_KB >> 10} MiB")
    peak_before = max(peak_before, peak)
    if "Sanitizer" in err or "runtime error:" in err:
        problems.append("sanitizer report")
    if problems:
        failures.append(f"FAIL: {name}: {'; '.join(problems)}\n  stderr: {err.strip()[:700]}")
    else:
        print(f"ok: {name}: exit {code} in {cpu:.1f} s of processor time")


TRI = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
OUT = ["--size", "32x32", "-o", path("out.png")]

# ---- the memory estimate counts the .mtl ----
write("mtl/big.mtl", "".join(f"newmtl m{i}\nKd 1 0 0\n" for i in range(100000)))
BIG_MTL = write("mtl/m.obj", "mtllib big.mtl\n" + TRI + "usemtl m1\nf 1 2 3\n")
case("a 90-byte OBJ with 100,000 materials", ["--model", BIG_MTL] + OUT, 2,
     "with its materials, objects and groups needs about")
case("the same under --memory-limit 256", ["--model", BIG_MTL, "--memory-limit", "256"] + OUT, 2,
     "over the memory limit of 256 MiB (set by --memory-limit)")
SMALL_MTL = write("mtl/small.mtl", "newmtl red\nKd 1 0 0\n")
case("an OBJ with a small .mtl", ["--model", write("mtl/ok.obj", "mtllib small.mtl\n" + TRI +
                                                   "usemtl red\nf 1 2 3\n")] + OUT, 0, "wrote")

# ---- 'g' groups counted in the estimate (3.4 KB each) ----
# 100,000 'g' groups in 1.7 MB: assimp takes 342 MB (a mesh a group), which
# the estimate (20 bytes a byte: 34 MB) let through before; now 356 MiB with
# the groups, refused before the import under --memory-limit 256. 20,000
# (their time is linear, unlike objects') still render within it.
GROUPS = write("groups.obj", TRI + "".join(f"g a{i}\nf 1 2 3\n" for i in range(100000)))
case("100,000 'g' groups under --memory-limit 256", ["--model", GROUPS, "--memory-limit", "256"]
     + OUT, 2, "(1.7 MB) with its materials, objects and groups needs about 356 MiB, over the "
     "memory limit of 256 MiB")
case("20,000 'g' groups under --memory-limit 256", ["--model", write("groups20k.obj", TRI + "".join(
    f"g a{i}\nf 1 2 3\n" for i in range(20000))), "--memory-limit", "256"] + OUT, 0, "wrote")

# ---- the import's child held to the budget (RLIMIT_AS), past what the estimate sees ----
# 300,000 'l' polylines of 8 points and one face in 5.4 MB: the estimate (20
# bytes a byte: 108 MB) lets it through, assimp takes 453 MB (80 bytes a
# byte); under --memory-limit 256 the child's address-space limit stops it.
# Not under ASan (no RLIMIT_AS there).
if not SANITIZED:
    case("300,000 'l' polylines under --memory-limit 256", ["--model", write("lines.obj", TRI + "".join(
        "l 1 2 3 1 2 3 1 2\n" for i in range(300000)) + "f 1 2 3\n"), "--memory-limit", "256"] + OUT,
        2, "needs more memory than the budget (256 MiB, set by --memory-limit) while it is imported")

# ---- assimp's OBJ reader is quadratic in objects and material switches ----
case("100,000 'o' objects", ["--model", write("objects.obj", TRI + "".join(
    f"o a{i}\nf 1 2 3\n" for i in range(100000)))] + OUT, 2,
    "has 100000 objects ('o' lines) and 0 material switches")
case("a material switch on each of 100,000 faces", ["--model", write("mtl/switch.obj",
     "mtllib small.mtl\n" + TRI + "".join(f"usemtl m{i}\nf 1 2 3\n" for i in range(100000)))] + OUT,
     2, "and 100000 material switches ('usemtl' lines); expected at most 20000")

# ---- a model named by many objects is imported once ----
write("tri.obj", TRI + "f 1 2 3\n")
MANY = write("many.json", json.dumps({"objects": [{"model": "tri.obj"}] * 4096}))
case("a scene naming one OBJ in 4,096 objects", ["--scene", MANY] + OUT, 0, "wrote")

# ---- a PLY header cut short or misspelt: refused at once ----
case("a PLY cut inside its header", ["--model", write("cut.ply",
     "ply\nformat ascii 1.0\nelement vertex 3\nprop")] + OUT, 2,
     "its PLY header ends at line 4 without 'end_header'")
case("a PLY with end_header misspelt", ["--model", write("misspelt.ply",
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_heder\n0\n1\n2\n")] + OUT, 2,
     "line 5 of its PLY header, 'end_heder', is not one of")
case("a PLY whose name says OBJ, cut inside its header", ["--model", write("cut_ply.obj",
     "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar")] + OUT, 2,
     "its PLY header ends at line 4 without 'end_header'")

# ---- mtllib stays in the model's folder ----
os.symlink("/etc/passwd", path("mtl/link.mtl"))
for k, name in enumerate(("../../../../../../etc/passwd", "/proc/self/environ", "link.mtl")):
    case(f"mtllib {name}", ["--model", write(f"mtl/out{k}.obj", f"mtllib {name}\n" + TRI +
                                             "f 1 2 3\n")] + OUT, 2,
         f"line 1: mtllib '{name}' points outside the model's folder")

# ---- texture coordinate and normal indices ----
case("a vt index past the vt lines", ["--model", write("vt.obj", TRI + "vt 0 0\nf 1/1 2/2 3/1\n")]
     + OUT, 2, "line 5: a face uses texture coordinate (vt) index 2, but the file defines only 1")
case("a vn index with no vn lines", ["--model", write("vn.obj", TRI + "f 1//1 2//1 3//1\n")] + OUT,
     2, "line 4: a face uses normal (vn) index 1, but the file defines none before it")
case("a negative vt index past the start", ["--model", write("vt_neg.obj",
     TRI + "vt 0 0\nvt 1 0\nf 1/-1 2/-2 3/-3\n")] + OUT, 2, "texture coordinate (vt) index -3")
case("good vt/vn indices, relative and absolute", ["--model", write("vtvn_ok.obj",
     TRI + "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/-2/-1 3/3/1\n")] + OUT, 0, "wrote")

# ---- a slow import: past the run's total, and killed with its parent ----
# 19,999 objects, each with its own material switch (under the limit of
# 20,000 of each): several CPU seconds in assimp's quadratic OBJ reader.
SLOW = write("slow.obj", "".join(f"o a{i}\nusemtl m{i}\nv {i} 0 0\nv 1 {i} 0\nv 0 1 {i}\n"
                                 "f -3 -2 -1\n" for i in range(19999)))
TOTAL = write("total.json", json.dumps({"objects": [{"model": "tri.obj"}, {"model": "slow.obj"}]}))
case("a scene's imports past RAS_MESH_IMPORT_TOTAL_SECONDS", ["--scene", TOTAL] + OUT, 2,
     f"importing '{SLOW}' ran past the limit on all of the scene's model imports (1 s",
     env={"RAS_MESH_IMPORT_TOTAL_SECONDS": "1"})

# ---- one budget for the run: --compare's reference and work counted up front (B6) ----
# At the largest legal size an 8192x8192 --compare held 5.2 GB under the 2 GiB
# default, and under a 4 GiB cap its "out of memory" was exit 1 ("differ").
H2 = os.path.join(BIN, "hw2_rasterize_ref")


def grey_png(name, side):
    """A valid side x side grey RGB PNG, written here (a 65 KB file for 8192)."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    row = b"\0" + b"\x80" * (3 * side)
    packer = zlib.compressobj(9)
    idat = b"".join(packer.compress(row) for _ in range(side)) + packer.flush()
    with open(path(name), "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", side, side, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", idat) + chunk(b"IEND", b""))
    return path(name)


REF8K = grey_png("ref8k.png", 8192)
# With the default budget the frame alone is over it (found first); with 4096
# MiB the frame fits and the reference with the comparison's work does not.
for limit, says in (([], "a 8192x8192 frame with 1 sample per pixel needs about"),
                    (["--memory-limit", "4096"],
                     "(a 8192x8192 reference and the comparison's work) needs about")):
    case(f"--compare at 8192x8192 {' '.join(limit) or 'with the default budget'}",
         ["--compare", "--reference", REF8K, "--size", "8192x8192"] + limit +
         ["-o", path("cmp8k.png")], 2, says, program=H2)


# ---- one budget for the run: the frame's writing and --dump's buffers (B6) ----
# A legal run that the estimate lets through must stay within the limit it was
# let through under: hw2 at 8192x8192 held 2,179 MB under the 2 GiB default
# (the picture's encoding was not counted), and hw3's --dump held its buffers
# outside the budget (3.5 GB at 2048x2048 with 16 samples). Each size below
# is run at a limit just under what it takes (refused up front, exit 2) and
# at one above (drawn, its own peak within the limit): with the old estimate
# the first was drawn and went over its limit.


def run_own_peak(args, program):
    """(exit status, stderr, peak KiB of this run alone): wait4 gives the
    child's own rusage, where RUSAGE_CHILDREN keeps the largest so far."""
    with open(path("own_peak.err"), "w+b") as err:
        p = subprocess.Popen([program] + args, stdout=subprocess.DEVNULL, stderr=err, cwd=WORK,
                             env={k: v for k, v in os.environ.items()
                                  if k not in ("DISPLAY", "WAYLAND_DISPLAY", "RAS_MEMORY_LIMIT_MB")},
                             start_new_session=True)
        try:
            _, status, usage = os.wait4(p.pid, 0)
        finally:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
        p.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        return p.returncode, err.read().decode(errors="replace"), usage.ru_maxrss


def within_its_limit(name, args, program, under, over):
    code, err, _ = run_own_peak(args + ["--memory-limit", str(under)], program)
    if code != 2 or "needs about" not in err:
        failures.append(f"FAIL: {name} under --memory-limit {under}: expected a refusal up front "
                        f"(exit 2, 'needs about'), got exit {code}\n  stderr: {err.strip()[:500]}")
    else:
        print(f"ok: {name} under --memory-limit {under}: refused up front")
    code, err, peak = run_own_peak(args + ["--memory-limit", str(over)], program)
    if code != 0 or peak > over << 10:
        failures.append(f"FAIL: {name} under --memory-limit {over}: expected it drawn within the "
                        f"limit, got exit {code} with a peak of {peak >> 10} MiB\n"
                        f"  stderr: {err.strip()[:500]}")
    else:
        print(f"ok: {name} under --memory-limit {over}: drawn, peak {peak >> 10} MiB")


case("hw2 at 8192x8192 (the largest legal size) under a 2048 MiB budget",
     ["--size", "8192x8192", "--memory-limit", "2048", "-o", path("8k.png")], 2,
     "a 8192x8192 frame with 1 sample per pixel needs about", program=H2)
case("hw3 --dump at 2048x2048 with 16 samples under a 2048 MiB budget",
     ["--size", "2048x2048", "--aa", "ssaa", "--samples", "16", "--memory-limit", "2048",
      "-o", path("d2k.png"), "--dump", path("d2k")], 2,
     "--dump of a 2048x2048 frame with 16 samples per pixel needs about")
if not SANITIZED:  # ASan's shadow memory is resident too
    within_its_limit("hw2 at 4096x4096", ["--size", "4096x4096", "-o", path("4k.png")], H2,
                     520, 600)
    within_its_limit("hw3 --dump at 1024x1024 with 16 samples",
                     ["--size", "1024x1024", "--aa", "ssaa", "--samples", "16", "-o",
                      path("d1k.png"), "--dump", path("d1k")], H3, 900, 1100)

PR_SET_CHILD_SUBREAPER = 36


def children_of(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(c) for c in f.read().split()]
    except OSError:
        return []


def killed_mid_import(sig):
    """Kills the program with `sig` while its import child works; the child
    must end by SIGKILL (its parent-death signal). This process is the
    subreaper, so the orphan comes to it and its end is seen exactly."""
    p = subprocess.Popen([H3, "--model", SLOW] + OUT, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, cwd=WORK, start_new_session=True)
    deadline = time.monotonic() + SECONDS
    kids = []
    while not kids and time.monotonic() < deadline and p.poll() is None:
        time.sleep(0.05)
        kids = children_of(p.pid)
    if not kids:
        p.kill()
        p.wait()
        return f"FAIL: killed by signal {sig}: no import child was seen"
    time.sleep(0.3)  # the child is importing (the whole import takes seconds)
    os.kill(p.pid, sig)
    p.wait()
    problems = []
    for kid in kids:
        # Ours once orphaned (we are the subreaper). SIGKILL is immediate;
        # 5 s is for a busy machine.
        status, waited = None, time.monotonic() + 5
        try:
            while status is None and time.monotonic() < waited:
                pid, st = os.waitpid(kid, os.WNOHANG)
                status = st if pid == kid else None
                time.sleep(0.02)
        except ChildProcessError:
            problems.append(f"the import child {kid} did not come to the subreaper")
            continue
        if status is None:
            os.kill(kid, signal.SIGKILL)
            os.waitpid(kid, 0)
            problems.append(f"the import child {kid} was still running 5 s after its parent died")
            continue
        if not (os.WIFSIGNALED(status) and os.WTERMSIG(status) == signal.SIGKILL):
            how = (f"exit {os.WEXITSTATUS(status)}" if os.WIFEXITED(status)
                   else f"signal {os.WTERMSIG(status)}")
            problems.append(f"the import child {kid} outlived its parent and ended by {how}, "
                            "expected SIGKILL the moment the parent died")
    if problems:
        return f"FAIL: program killed by signal {sig} mid-import: {'; '.join(problems)}"
    print(f"ok: program killed by signal {sig} mid-import: its import child was killed with it")
    return None


libc = ctypes.CDLL(None, use_errno=True)
if libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) != 0:
    failures.append("FAIL: could not become a subreaper (prctl), so the import child's end "
                    "cannot be seen")
else:
    for sig in (signal.SIGTERM, signal.SIGKILL):
        result = killed_mid_import(sig)
        if result:
            failures.append(result)

for f in failures:
    print(f)
print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
