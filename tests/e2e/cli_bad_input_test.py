#!/usr/bin/env python3
"""cli_bad_input_test.py — the programs and tools given bad input, from outside.

    cli_bad_input_test.py BIN_DIR WORK_DIR

The project standard: bad input (files, scenes, numbers, flags) gets a clear
error and a non-zero exit (2 for usage and input errors), nothing half
written is left behind, no crash, no sanitizer finding. For each case below
this runs one of build/bin/{hw1_transform,hw2_rasterize,hw3_shading}_ref,
raster101-compare or raster101-grade and checks
  - the exit status,
  - a piece of the message on stderr (what was expected / what came),
  - that the output file named on the command line does not exist afterwards,
  - that stderr carries no AddressSanitizer / UBSan report.
A few good runs are checked as well, so the checks cannot pass by accident.
The robustness cases (disk full, special files, memory bombs, deep
models) run as a user would meet them: under a 1 GiB address-space cap
(prlimit --as; not under ASan, whose shadow memory needs terabytes of address
space: the cap is left off when the programs link libasan, and
RAS_MEMORY_LIMIT_MB=528 gives the budget the cap would) and 20 s of processor
time (prlimit --cpu; the wall clock only guards against a hang: 120 s), with a good output file already in
place that must come out byte-identical, and no temporary file (.NAME-XXXXXX)
left beside it.
Every bad case fails before rendering; the cases run in parallel, each with
its own output name, so the whole run takes seconds (most of it is process
start-up, slow under ASan).
Exit status 0 when every check passes; each failure is printed.
"""
import concurrent.futures
import glob
import os
import signal
import shutil
import subprocess
import sys

import e2e_common

BIN, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
SANITIZED = e2e_common.sanitized(BIN, "hw1_transform_ref")
AS_CAP = 1 << 30  # the robustness cases' address-space cap, bytes
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
failures = []

def path(name):
    return os.path.join(WORK, name)

def write(name, data):
    with open(path(name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)
    return path(name)

EMPTY = write("empty.json", "")
BINARY = write("binary.json", bytes(range(256)) * 4)
CORRUPT_PNG = write("corrupt.png", b"\x89PNG\r\n\x1a\n" + bytes(range(200)))
OK_OBJ = write("ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
MISSING_MODEL_SCENE = write("missing_model.json", '{"objects": [{"model": "no-such-model.obj"}]}')
CORRUPT_TEXTURE_SCENE = write("corrupt_texture.json",
                              '{"shader": "texture", "objects": [{"shape": "cube", "material": '
                              '{"texture": {"file": "%s"}}}]}' % CORRUPT_PNG)
HUGE_NUMBER_SCENE = write("huge_number.json",
                          '{"image": {"width": 1e999, "height": 10}, "objects": [{"shape": "cube"}]}')
CUBE_SCENE = write("cube.json", '{"objects": [{"shape": "cube"}]}')
A_FOLDER = path("folder.png")  # a folder whose name looks like an image
os.makedirs(A_FOLDER)
OUT = "<OUT>"  # in a case's arguments: that case's own output file, WORK/out<N>.png
cases = []

def run(program, args, limits=None, timeout=120, env_extra=None):
    """limits: prlimit options (e.g. ["--as=1073741824"]) the program runs under."""
    env = dict(os.environ)
    env.pop("DISPLAY", None)  # no window: every case is headless or a "no display" error
    env.pop("WAYLAND_DISPLAY", None)
    env.pop("RAS_MEMORY_LIMIT_MB", None)
    env.update(env_extra or {})
    cmd = [os.path.join(BIN, program)] + args
    if limits:
        cmd = ["prlimit"] + limits + ["--"] + cmd
    if env_extra and env_extra.get("AS_NOBODY"):  # root reads everything: drop to nobody
        cmd = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"] + cmd
        env.pop("AS_NOBODY")
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout,
                           cwd=WORK, errors="replace")
    except subprocess.TimeoutExpired:
        return "timeout", "", f"(killed after {timeout} s)"
    return p.returncode, p.stdout, p.stderr

def case(program, args, status, message, absent=(OUT,), stdout_has=None, present=(),
         hard=False, keep=None, fsize=None, env=None, ext="png"):
    """One case: `message` must appear in stderr (stdout_has in stdout), the
    files `absent` must not exist afterwards and those `present` must.
    hard: a robustness case, run under the 1 GiB address-space cap and 20 s of
    processor time; status "nonzero" accepts any failure that is not a signal.
    keep: a file put at the case's output before the run, which must be
    unchanged after it (absent is then ignored for OUT). fsize: RLIMIT_FSIZE.
    ext: the extension of the case's output file."""
    cases.append((len(cases), program, args, status, message, absent, stdout_has, present,
                  hard, keep, fsize, env, ext))

def check(c):
    n, program, args, status, message, absent, stdout_has, present, hard, keep, fsize, env, ext = c
    out_path = path(f"out{n}.{ext}")
    args = [out_path if a == OUT else a for a in args]
    absent = [out_path if a == OUT else a for a in absent if not (keep and a == OUT)]
    present = [out_path if a == OUT else a for a in present]
    before = None
    if keep:
        shutil.copyfile(keep, out_path)
        with open(out_path, "rb") as f:
            before = f.read()
    limits = []
    if hard and not SANITIZED:
        limits.append(f"--as={AS_CAP}")
    elif hard and not (env and "RAS_MEMORY_LIMIT_MB" in env):
        # No cap under ASan: the budget the cap would give, set directly.
        env = dict(env or {}, RAS_MEMORY_LIMIT_MB="528")
    if fsize is not None:
        limits.append(f"--fsize={fsize}")
    if hard:
        # 20 s of processor time, not of the wall: on a loaded machine (or
        # under ASan) a case that needs 5 s of it can take 20 s of the wall.
        # The wall clock below only guards against a hang.
        limits.append("--cpu=20")
    code, out, err = run(program, args, limits, timeout=120, env_extra=env)
    what = f"{program} {' '.join(args)}"
    problems = []
    if code == -signal.SIGXCPU:
        problems.append("over its 20 s of processor time (killed by SIGXCPU)")
    if status == "nonzero":
        if code == "timeout" or code == 0 or code < 0 or code >= 128:
            problems.append(f"exit {code}, expected a non-zero status (not a signal)")
    elif code != status:
        problems.append(f"exit {code}, expected {status}")
    if before is not None:
        try:
            with open(out_path, "rb") as f:
                if f.read() != before:
                    problems.append(f"{out_path} was changed")
        except OSError:
            problems.append(f"{out_path} was lost")
    leftovers = glob.glob(os.path.join(glob.escape(WORK), f".out{n}.{ext}-*"))
    problems += [f"temporary file {t} was left behind" for t in leftovers]
    if message and message not in err:
        problems.append(f"stderr lacks {message!r}")
    if stdout_has and stdout_has not in out:
        problems.append(f"stdout lacks {stdout_has!r}")
    problems += [f"{f} was left behind" for f in absent if os.path.exists(f)]
    problems += [f"{f} was not written" for f in present if not os.path.isfile(f)]
    if "Sanitizer" in err or "runtime error:" in err:
        problems.append("sanitizer report")
    if status in (2, "nonzero") and not err.startswith(program.replace("_ref", "") + ":"):
        problems.append("stderr does not start with the program's name")
    if problems:
        return f"FAIL: {what}: {'; '.join(problems)}\n  stderr: {err.strip()[:600]}"
    return None

REF = path("ref.png")  # a small good image, for raster101-compare and --reference
code, _, err = run("hw2_rasterize_ref", ["--size", "16x16", "-o", REF])
if code != 0:
    failures.append(f"could not make {REF}: {err}")
# The programs: those of the reference catalogue (tests/reference/catalogue.json).
PROGRAMS = [p + "_ref" for p in subprocess.run(
    [os.path.join(BIN, "raster101-catalogue"), "programs"], capture_output=True, text=True,
    check=True).stdout.split()]

# ---- what every program shares (common/app/ras_cli.c, ras_image_check_output) ----
# Each main checks -o, the display and the scene itself: those cases run on all
# three programs. The parser is one for all: its cases take turns (each process
# start costs ~0.3 s under ASan).
for p in PROGRAMS:
    case(p, ["--help"], 0, "", stdout_has="Exit status")
case(PROGRAMS[0], ["--version"], 0, "", stdout_has="Raster101")
for p in PROGRAMS:
    case(p, [], 2, "no display to open a window on")
    case(p, ["-o", path("out.txt")], 2, "expected an image extension", absent=(path("out.txt"),))
    case(p, ["--scene", MISSING_MODEL_SCENE, "-o", OUT], 2, "no-such-model.obj")
    case(p, ["--size", "16x16", "-o", OUT], 0, "wrote", absent=(), present=(OUT,))
# --dump (common/pipeline/ras_dump.h): only with a headless frame, only into a folder;
# each program writes its own buffers (hw1 its vertices).
case(PROGRAMS[0], ["--dump", path("dump-none")], 2,
     "--dump DIR writes the buffers of one headless frame", absent=(path("dump-none"),))
case(PROGRAMS[1 % len(PROGRAMS)], ["-o", OUT, "--dump", REF], 2,
     "--dump expects a folder", keep=REF)
for p, first in zip(PROGRAMS, ["vertices.json", "depth.pfm", "normal.json"]):
    dump = path("dump-" + p)
    case(p, ["--size", "32x24", "-o", OUT, "--dump", dump], 0, "wrote the frame's buffers",
         absent=(), present=(OUT, os.path.join(dump, first)))
shared = [
    (["--bogus", "-o", OUT], 2, "unknown option '--bogus'"),
    (["-q", "-o", OUT], 2, "unknown option '-q'"),
    (["--stats=1", "-o", OUT], 2, "'--stats' takes no value"),
    (["--s", "9", "-o", OUT], 2, "ambiguous"),
    (["-o"], 2, "needs a value: expected an output FILE"),
    (["-o", "--size", "9x9"], 2, "got '--size', which looks like an option"),
    (["-o", ""], 2, "got an empty name"),
    (["-o", path("out")], 2, "expected a file name with an image extension"),
    (["-o", path("no-such-folder/out.png")], 2, "no-such-folder' does not exist; create it"),
    (["-o", A_FOLDER], 2, "it is a folder"),
    (["-o", EMPTY + "/out.png"], 2, "is a file, not a folder"),
    (["--scene", path("no-such-scene.json"), "-o", OUT], 2, "cannot open the scene file"),
    (["--scene", WORK, "-o", OUT], 2, "expected a scene file, got a folder"),
    (["--scene", EMPTY, "-o", OUT], 2, "expected a JSON object"),
    (["--scene", BINARY, "-o", OUT], 2, "binary.json"),
    (["--scene", HUGE_NUMBER_SCENE, "-o", OUT], 2, "image.width"),
] + [(["--size", size, "-o", OUT], 2, f"--size expects WIDTHxHEIGHT between 1x1 and "
      f"8192x8192, e.g. --size 700x700; got '{size}'")
     for size in ["0", "99999", "10x10junk"]]
for k, (args, status, message) in enumerate(shared):
    case(PROGRAMS[k % len(PROGRAMS)], args, status, message)

# ---- hw1 ----
H1 = "hw1_transform_ref"
for angle in ["abc", "1e999"]:
    case(H1, ["-r", angle, "-o", OUT], 2, f"--angle expects a finite number of degrees, e.g. -r "
         f"20; got '{angle}'")
for axis in ["0,0,0", "nan,1,1"]:
    case(H1, ["--axis", axis, "-o", OUT], 2, f"--axis expects three numbers X,Y,Z, not all "
         f"zero, e.g. --axis 0,1,0; got '{axis}'")
case(H1, ["--samples", "4", "-o", OUT], 2, "'--samples' does not apply to this program")
case(H1, ["-o", OUT, path("b.png")], 2, "unexpected argument", absent=(OUT, path("b.png")))
case(H1, ["-r", "20", OUT], 0, "wrote", absent=(), present=(OUT,))  # the classic positional form

# ---- hw2 ----
H2 = "hw2_rasterize_ref"
case(H2, ["--samples", "3", "-o", OUT], 2, "has no 3-sample version")
case(H2, ["--samples", "1000", "-o", OUT], 2, "--samples expects a whole number")
case(H2, ["--aa", "bogus", "-o", OUT], 2, "--aa expects none, msaa or ssaa; got 'bogus'")
case(H2, ["--pattern"], 2, "'--pattern' needs a value: expected ordered or standard")
case(H2, ["--depth", "reversed", "-o", OUT], 2, "--depth expects z01 or inverse_w; got 'reversed'")
case(H2, ["--depth", "inverse_w", "--size", "16x16", "-o", OUT], 0, "wrote", absent=(),
     present=(OUT,))
case(H2, ["--aa", "none", "--samples", "4", "-o", OUT], 2, "--aa none draws one sample")
case(H2, ["--samples", "8", "--size", "16x16", "-o", OUT], 0, "wrote", absent=(), present=(OUT,))
case(H2, ["--reference", CORRUPT_PNG, "-o", OUT], 2, "--reference FILE goes with --compare")
case(H2, ["--compare", "--aa", "msaa", "--samples", "16", "-o", OUT], 2,
     "no reference image for these settings; hw2_rasterize's references")
case(H2, ["--compare", "--reference", CORRUPT_PNG, "-o", OUT], 2, "--reference: could not read")
case(H2, ["--compare", "--size", "64x64", "-o", path("cmp2.png")], 2,
     "render at the reference's size", absent=(path("cmp2.png"), path("cmp2_diff.png")))
case(H2, ["--compare", "--scene", CUBE_SCENE, "-o", OUT], 2, "needs --reference FILE")
case(H2, ["--compare", "--reference", REF, "-o", REF], 2, "would overwrite the --reference",
     absent=(), present=(REF,))
case(H2, ["--size", "8192x8192", "--aa", "ssaa", "--samples", "64", "-o", OUT], 2,
     "use a smaller --size or fewer --samples")
case(H2, ["--shader", "phong", "-o", OUT], 2, "'--shader' does not apply to this program")

# ---- hw3 ----
H3 = "hw3_shading_ref"
case(H3, ["--shader", "bogus", "-o", OUT], 2, "--shader expects normal, phong")
case(H3, ["phong", OUT], 2, "--shader expects")  # positional arguments in the wrong order
case(H3, ["-o", OUT, path("b.png")], 2, "unexpected argument", absent=(OUT, path("b.png")))
# One rule set (common/app/ras_app.h): --samples N alone means MSAA in every program.
case(H3, ["--samples", "8", "--size", "16x16", "-o", OUT], 0, "wrote", absent=(), present=(OUT,))
case(H3, ["--aa", "none", "--samples", "4", "-o", OUT], 2, "--aa none draws one sample")
case(H3, ["--compare", "--filter", "nearest", "-o", OUT], 2,
     "no reference image for these settings; hw3_shading's references")
case(H3, ["--texture", OK_OBJ, "-o", OUT], 2, "go with --model FILE")
case(H3, ["--compare", "--size", "64x64", "-o", path("cmp3.png")], 2,
     "render at the reference's size", absent=(path("cmp3.png"), path("cmp3_diff.png")))
case(H3, ["--compare", "--scene", CUBE_SCENE, "-o", OUT], 2, "needs --reference FILE")
case(H3, ["--compare", "--reference", path("no-such.png"), "-o", OUT], 2,
     "--reference: could not read image")
case(H3, ["--model", path("no-such.obj"), "-o", OUT], 2, "cannot open model file")
case(H3, ["--model", OK_OBJ, "--texture", CORRUPT_PNG, "-o", OUT], 2, "corrupt.png")
case(H3, ["--size", "8192x8192", "--aa", "ssaa", "--samples", "64", "-o", OUT], 2,
     "use a smaller --size or fewer --samples")
case(H3, ["--model", OK_OBJ, "--size", "16x16", "-o", OUT], 0, "wrote", absent=(),
     present=(OUT,))

# ---- raster101-compare ----
C = "raster101-compare"
case(C, ["--metric", "exact", REF, REF], 0, "", absent=())
case(C, ["--metric", "exact", REF], 2, "expected two images, EXPECTED and GOT; got 1 argument",
     absent=())
case(C, [REF, REF], 2, "expected --metric", absent=())
for tol in ["1e999", "nan"]:
    case(C, ["--metric", "exact", "--tolerance", tol, REF, REF], 2, f"got '{tol}'", absent=())
case(C, ["--metric", "edge", "--max-bad", "-3", REF, REF], 2, "--max-bad expects", absent=())
case(C, ["--metric", "exact", REF, CORRUPT_PNG], 2, "got image: could not read", absent=())
case(C, ["--metric", "exact", "--diff", path("no-such-folder/d.png"), REF, REF], 2,
     "does not exist", absent=())
case(C, ["--metric", "exact", "--crop", path("crop.txt"), REF, REF], 2,
     "expected an image extension", absent=(path("crop.txt"),))

# ---- raster101-grade (argument checks only: no grading is run) ----
G = "raster101-grade"
SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.dirname(os.path.abspath(BIN))
GOUT = path("grade-out")
case(G, ["--bogus", "x"], 2, "unknown argument '--bogus'", absent=(GOUT,))
case(G, ["--source", SRC, "--build", BUILD], 2, "--out is missing", absent=(GOUT,))
case(G, ["--source", SRC, "--build", BUILD, "--out", GOUT, "--expect", "abc"], 2,
     "--expect expects full or a number", absent=(GOUT,))
case(G, ["--source", path("no-such-src"), "--build", BUILD, "--out", GOUT], 2,
     "is not a folder", absent=(GOUT,))
case(G, ["--source", SRC, "--build", BUILD, "--out", GOUT, "--hw", "hw9"], 2,
     "--hw expects an assignment", absent=(GOUT,))
case(G, ["--source", SRC, "--build", BUILD, "--out", EMPTY, "--hw", "hw1"], 2,
     "it is a file", absent=())

# ---- writes are atomic and verified (common/io/ras_io.c) ----
# A file-size limit one byte short of the picture (the disk-full repro: the
# error lands in the last bytes), PNG, BMP and PPM, every writer: the good
# file already there stays byte-identical, no temporary file is left.
case(H3, ["--shader", "phong", "-o", OUT], "nonzero", "File too large", hard=True, keep=REF,
     fsize=100252)
case(H1, ["-o", OUT], "nonzero", "was left as it was", hard=True, keep=REF, fsize=4096, ext="bmp")
case(H2, ["-o", OUT], "nonzero", "File too large", hard=True, keep=REF, fsize=4096, ext="ppm")
case(C, ["--metric", "exact", "--diff", OUT, REF, REF], "nonzero", "File too large", hard=True,
     keep=REF, fsize=10)
# The longest valid name (255 bytes) works: the temporary name is cut to fit.
LONG_NAME = path("n" * 251 + ".png")
case(H1, ["--size", "16x16", "-o", LONG_NAME], 0, "wrote", absent=(), present=(LONG_NAME,),
     hard=True)
# A good write over a good file replaces it.
case(H2, ["--size", "16x16", "--aa", "msaa", "-o", OUT], 0, "wrote", absent=(), present=(OUT,),
     hard=True)

# ---- only regular files are read (ras_io_open_input) ----
# A FIFO with no writer would block forever; a device never ends; both are
# refused at once, by type, wherever a file is read.
FIFO = path("fifo.obj")
os.mkfifo(FIFO)
FIFO_PNG = path("fifo.png")
os.mkfifo(FIFO_PNG)
FIFO_JSON = path("fifo.json")
os.mkfifo(FIFO_JSON)
FIFO_MTL_OBJ = write("fifo_mtl.obj", "mtllib fifo.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
os.mkfifo(path("fifo.mtl"))
FIFO_TEXTURE_SCENE = write("fifo_texture.json",
                           '{"shader": "texture", "objects": [{"shape": "cube", "material": '
                           '{"texture": {"file": "%s"}}}]}' % FIFO_PNG)
GOT_FIFO = "expected a regular file, got a FIFO"
case(H2, ["-o", FIFO_PNG], 2, "it is a FIFO; expected a regular file", absent=(), hard=True)
case(H3, ["--model", FIFO, "-o", OUT], "nonzero", GOT_FIFO, hard=True, keep=REF)
case(H3, ["--model", OK_OBJ, "--texture", FIFO_PNG, "-o", OUT], "nonzero", GOT_FIFO, hard=True,
     keep=REF)
case(H3, ["--model", OK_OBJ, "--texture", "/dev/zero", "-o", OUT], "nonzero",
     "got a character device", hard=True, keep=REF)
case(H3, ["--model", OK_OBJ, "--texture", WORK, "-o", OUT], "nonzero", "got a folder",
     hard=True, keep=REF)
case(H3, ["--model", FIFO_MTL_OBJ, "--size", "16x16", "-o", OUT], 0, "wrote", absent=(),
     present=(OUT,), hard=True)  # a FIFO named by the model is skipped, not waited for
case(H1, ["--scene", FIFO_JSON, "-o", OUT], "nonzero", GOT_FIFO, hard=True, keep=REF)
case(H3, ["--scene", FIFO_TEXTURE_SCENE, "-o", OUT], "nonzero", GOT_FIFO, hard=True, keep=REF)
case(H2, ["--compare", "--reference", FIFO_PNG, "-o", OUT], "nonzero", GOT_FIFO, hard=True,
     keep=REF)
case(H3, ["--compare", "--reference", "/dev/zero", "-o", OUT], "nonzero",
     "got a character device", hard=True, keep=REF)
case(C, ["--metric", "exact", FIFO_PNG, REF], "nonzero", GOT_FIFO, absent=(), hard=True)
case(C, ["--metric", "exact", REF, FIFO_PNG], "nonzero", GOT_FIFO, absent=(), hard=True)
# A --reference path longer than the programs take is refused by name, not cut.
LONG_REF = os.path.join(WORK, "./" * 600 + "ref.png")
case(H2, ["--compare", "--reference", LONG_REF, "-o", OUT], 2,
     "--reference expects a file name of at most 1023 bytes", hard=True, keep=REF)
# An existing file that cannot be read says so (root reads everything: run as
# nobody through setpriv, when the folders let nobody in).
UNREADABLE = write("unreadable.png", open(REF, "rb").read())
os.chmod(UNREADABLE, 0)
UNREADABLE_OBJ = write("unreadable.obj", open(OK_OBJ).read())
os.chmod(UNREADABLE_OBJ, 0)
if os.geteuid() != 0:
    case(H3, ["--model", OK_OBJ, "--texture", UNREADABLE, "-o", OUT], "nonzero",
         "Permission denied", hard=True, keep=REF)
    case(C, ["--metric", "exact", UNREADABLE, REF], "nonzero", "Permission denied", absent=(),
         hard=True)
elif shutil.which("setpriv") and subprocess.run(
        ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups", "test", "-r", REF]
        ).returncode == 0:
    NOBODY = {"AS_NOBODY": "1"}
    case(C, ["--metric", "exact", UNREADABLE, REF], "nonzero",
         "could not read image '%s': Permission denied" % UNREADABLE, absent=(), hard=True,
         env=NOBODY)
    case(C, ["--metric", "exact", REF, UNREADABLE_OBJ], "nonzero", "Permission denied",
         absent=(), hard=True, env=NOBODY)

# ---- the memory budget (common/base/ras_memory.c) ----
# Each of these asked for gigabytes before: refused from the header or the
# scene's parameters, before the allocation, under the 1 GiB cap.
import struct
import zlib

def png_bomb(name, side, truncated=False):
    """A grey PNG of side x side zeros: a few hundred KB that decode to side² bytes
    (truncated: the header only, for sides too big to compress here quickly)."""
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    data = b""
    if not truncated:
        co = zlib.compressobj(6)
        row = b"\0" * (side + 1)
        data = b"".join(co.compress(row) for _ in range(side)) + co.flush()
    ihdr = struct.pack(">IIBBBBB", side, side, 8, 0, 0, 0, 0)
    return write(name, b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", data) +
                 chunk(b"IEND", b""))

BOMB16K = png_bomb("bomb16k.png", 16384)     # 261 KB -> 16384² (was decoded: 3.9 GB)
BOMB32K = png_bomb("bomb32k.png", 32768, truncated=True)  # (was 6.2 GB before refused)
BMP_BOMB = write("bomb.bmp", b"BM" + struct.pack("<IHHI", 54, 0, 0, 54) +
                 struct.pack("<IiiHHIIiiII", 40, 16000, 16000, 1, 24, 0, 0, 0, 0, 0, 0))
JPEG_BOMB = write("bomb.jpg", b"\xff\xd8\xff\xe0\x00\x10JFIF\x00\x01\x01\x00\x00\x01\x00\x01\x00"
                  b"\x00\xff\xc0\x00\x11\x08" + struct.pack(">HH", 16000, 16000) +
                  b"\x03\x01\x22\x00\x02\x11\x01\x03\x11\x01" + b"\x00" * 20)
PAM_BOMB = write("bomb.pam", b"P7\nWIDTH 16000\nHEIGHT 16000\nDEPTH 3\nMAXVAL 255\n"
                 b"TUPLTYPE RGB\nENDHDR\n" + b"\x00" * 30)
HDR_BOMB = write("bomb.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 40000 +X 40000\n" +
                 b"\x00" * 30)
TEAPOTS = write("teapots.json", '{"objects": [%s]}' % ", ".join(
    ['{"shape": "teapot", "divisions": 64}'] * 64))  # 3 KB (was 8.8 GB)
SPHERES = write("spheres.json", '{"objects": [%s]}' % ", ".join(
    ['{"shape": "sphere", "stacks": 1024, "slices": 1024}'] * 40))  # 1 KB (was 2.9 GB, 81 s)
BIG_MAPS = write("maps.json", '{"shader": "texture", "objects": [%s]}' % ", ".join(
    '{"shape": "cube", "material": {"texture": {"builtin": "%s", "size": 4096}}}' % b
    for b in ["checker", "brick", "bumps"]))  # 3 x 4096² textures with mips: 805 MiB
OVER = "over the memory limit"
case(H3, ["--model", OK_OBJ, "--texture", BOMB16K, "-o", OUT], "nonzero", OVER, hard=True,
     keep=REF)
case(H3, ["--model", OK_OBJ, "--texture", BOMB32K, "-o", OUT], "nonzero",
     "header says 32768x32768 pixels; expected 1..16384", hard=True, keep=REF)
case(H3, ["--model", OK_OBJ, "--texture", BMP_BOMB, "-o", OUT], "nonzero", OVER, hard=True,
     keep=REF)
case(H3, ["--model", OK_OBJ, "--texture", JPEG_BOMB, "-o", OUT], "nonzero",
     "bomb.jpg': it starts like a JPEG but its header does not say its size", hard=True,
     keep=REF)  # a frame header and no scan: libjpeg finds no complete header
# ---- every decoder bounded before it decodes, by content ----
# Formats whose size cannot be read first are refused by content, whatever
# their name (a Radiance HDR with 70 KB of header comments peaked at 2.1 GB).
LONG_HDR = write("long_hdr.png", b"#?RADIANCE\n" + (b"# " + b"x" * 1000 + b"\n") * 70 +
                 b"FORMAT=32-bit_rle_rgbe\n\n-Y 16000 +X 16000\n" + b"\x00" * 30)
for bomb, kind in ((PAM_BOMB, "a PAM image"), (HDR_BOMB, "a Radiance HDR image"),
                   (LONG_HDR, "a Radiance HDR image")):
    name = os.path.basename(bomb)
    case(H3, ["--model", OK_OBJ, "--texture", bomb, "-o", OUT], "nonzero",
         f"{name}': it is {kind}, a format not accepted here", hard=True, keep=REF)
    case(C, ["--metric", "exact", bomb, REF], "nonzero",
         f"{name}': it is {kind}, a format not accepted here", absent=(), hard=True)
def jpeg_sof(d):
    """Offset of a JPEG's frame header (SOFn) marker."""
    i = 2
    while not (0xC0 <= d[i + 1] <= 0xCF and d[i + 1] not in (0xC4, 0xC8, 0xCC)):
        i += 2 + (d[i + 2] << 8 | d[i + 3])
    return i
def jpeg_resized(d, w, h):
    i = jpeg_sof(d)
    return d[:i + 5] + struct.pack(">HH", h, w) + d[i + 9:]
BASE_JPG = path("base.jpg")
run("hw2_rasterize_ref", ["--size", "64x64", "-o", BASE_JPG])
base = open(BASE_JPG, "rb").read()
big = jpeg_resized(base, 16384, 16384)
# One junk byte before SOF0: a marker walk gave up at it, libjpeg skips it
# and decoded 16384² (3.9 GB). Its size now comes from libjpeg's own header call.
JUNK_JPG = write("junk_sof.jpg", big[:jpeg_sof(big)] + b"\x00" + big[jpeg_sof(big):])
JUNK_AS_BMP = write("junk_sof.bmp", open(JUNK_JPG, "rb").read())  # its name says BMP
for bomb in (JUNK_JPG, JUNK_AS_BMP):
    name = os.path.basename(bomb)
    case(H3, ["--model", OK_OBJ, "--texture", bomb, "-o", OUT], "nonzero",
         f"{name}' (16384x16384 pixels) needs about", hard=True, keep=REF)
    case(C, ["--metric", "exact", bomb, REF], "nonzero", f"{name}' (16384x16384) with",
         absent=(), hard=True)
# BigTIFF (II+): 16000² declared in 100 bytes (OpenCV decodes BigTIFF: 3.7 GB).
BIGTIFF = write("big.tif", b"II+\x00" + struct.pack("<HHQQ", 8, 0, 16, 2) +
                struct.pack("<HHQQ", 256, 4, 1, 16000) + struct.pack("<HHQQ", 257, 4, 1, 16000) +
                struct.pack("<Q", 0) + b"\x00" * 100)
case(H3, ["--model", OK_OBJ, "--texture", BIGTIFF, "-o", OUT], "nonzero",
     "big.tif' (16000x16000 pixels) needs about", hard=True, keep=REF)
case(C, ["--metric", "exact", BIGTIFF, REF], "nonzero", "big.tif' (16000x16000) with",
     absent=(), hard=True)
# A progressive JPEG with 2,000 scans (each a pass over every block: 17 CPU s
# at 8192²), made from a 617-byte seed by repeating its last scan: refused
# at scan 257, naming the limit; the same at 8192² is over the budget first.
SEED = open(os.path.join(SRC, "tests", "e2e", "data", "progressive.jpg"), "rb").read()
def many_scans(name, side, scans):
    d = jpeg_resized(SEED, side, side)
    last, end = d.rindex(b"\xff\xda"), d.rindex(b"\xff\xd9")
    return write(name, d[:end] + d[last:end] * scans + d[end:])
SCANS = many_scans("scans.jpg", 2048, 2000)
case(H3, ["--model", OK_OBJ, "--texture", SCANS, "-o", OUT], "nonzero",
     "scans.jpg': it has more than 256 scans", hard=True, keep=REF)
case(C, ["--metric", "exact", SCANS, REF], "nonzero", "scans.jpg': it has more than 256 scans",
     absent=(), hard=True)
case(H3, ["--model", OK_OBJ, "--texture", many_scans("scans8k.jpg", 8192, 20000), "-o", OUT],
     "nonzero", "scans8k.jpg' (8192x8192 pixels) needs about", hard=True, keep=REF)
# The time limit on every decode (RAS_IMAGE_DECODE_SECONDS), and a good
# progressive JPEG within the scan limit that renders.
OK_PROG = many_scans("prog_ok.jpg", 1024, 40)
case(H3, ["--model", OK_OBJ, "--texture", OK_PROG, "-o", OUT], 2,
     "prog_ok.jpg': decoding it took longer than the limit of 1e-06 s "
     "(RAS_IMAGE_DECODE_SECONDS)", hard=True, keep=REF,
     env={"RAS_IMAGE_DECODE_SECONDS": "0.000001"})
case(H3, ["--model", OK_OBJ, "--texture", OK_PROG, "--size", "16x16", "-o", OUT], 0, "wrote",
     absent=(), present=(OUT,), hard=True)
case(H3, ["--scene", TEAPOTS, "-o", OUT], "nonzero", "a teapot of 262144 triangles", hard=True,
     keep=REF)
case(H1, ["--scene", SPHERES, "-o", OUT], "nonzero", OVER, hard=True, keep=REF)
case(H3, ["--scene", BIG_MAPS, "-o", OUT], "nonzero", "a 4096x4096 texture", hard=True, keep=REF)
# A file's texture is held as its bytes (3 a texel, ras_texture.h), its float
# mips counted when trilinear filtering reads them: an 8192² grey PNG renders
# under the 1 GiB cap (its budget, 528 MiB: the decode is 384 MiB, then 192
# held; as floats it was refused, estimated at 1408 MiB); with the mips
# (256 MiB more) over a 400 MiB budget it is refused up front, exit 2.
GREY8K = png_bomb("grey8k.png", 8192)
case(H3, ["--model", OK_OBJ, "--texture", GREY8K, "--size", "16x16", "-o", OUT], 0, "wrote",
     absent=(), present=(OUT,), hard=True)
case(H3, ["--model", OK_OBJ, "--texture", GREY8K, "--shader", "texture", "--filter",
          "trilinear", "--size", "16x16", "--memory-limit", "400", "-o", OUT], 2,
     "building the mip levels of 1 texture for trilinear filtering needs about",
     hard=True, keep=REF)
case(H3, ["--model", OK_OBJ, "--texture", GREY8K, "--shader", "texture", "--filter",
          "trilinear", "--size", "16x16", "-o", OUT], 0, "wrote", absent=(), present=(OUT,),
     hard=True)
case(H1, ["--size", "8192x8192", "-o", OUT], 2, "a 8192x8192 frame with 1 sample per pixel needs",
     hard=True, keep=REF)
case(H2, ["--size", "4096x4096", "--aa", "ssaa", "--samples", "4", "-o", OUT], "nonzero",
     "a 4096x4096 frame with 4 samples per pixel needs about", hard=True, keep=REF)
case(C, ["--metric", "ssim", BOMB16K, BOMB16K], "nonzero",
     "bomb16k.png' (16384x16384) needs about",
     absent=(), hard=True)
case(H2, ["--compare", "--reference", BOMB16K, "-o", OUT], "nonzero", OVER, hard=True, keep=REF)
# The limit's two handles, and their bad values.
case(H2, ["--memory-limit", "16", "--size", "2048x2048", "--aa", "ssaa", "--samples", "4", "-o",
          OUT], "nonzero", "set by --memory-limit", hard=True, keep=REF)
case(H2, ["--size", "2048x2048", "--aa", "ssaa", "--samples", "4", "-o", OUT], "nonzero",
     "set by RAS_MEMORY_LIMIT_MB", hard=True, keep=REF, env={"RAS_MEMORY_LIMIT_MB": "16"})
case(H1, ["--memory-limit", "lots", "-o", OUT], 2, "--memory-limit expects a whole number of MiB",
     hard=True, keep=REF)
case(H3, ["-o", OUT], 2, "RAS_MEMORY_LIMIT_MB expects a whole number", hard=True, keep=REF,
     env={"RAS_MEMORY_LIMIT_MB": "-5"})
case(C, ["--metric", "exact", "--memory-limit", "0", REF, REF], 2, "--memory-limit expects",
     absent=(), hard=True)

# ---- deep models and deep JSON (common/io/ras_mesh_check.c, ras_scene.c) ----
def deep_gltf(name, levels):
    nodes = ",".join('{"children":[%d]}' % (k + 1) for k in range(levels - 1)) + ',{"mesh":0}'
    tri = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"  # 3 vec3 floats, base64
    return write(name, '{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],'
                 '"nodes":[%s],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],'
                 '"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",'
                 '"min":[0,0,0],"max":[1,1,0]}],"bufferViews":[{"buffer":0,"byteLength":36}],'
                 '"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,%s"}]}'
                 % (nodes, tri))
DEEP_GLTF = deep_gltf("deep.gltf", 20000)  # 450 KB: SIGSEGV in assimp before
DEEP_DAE = write("deep.dae", '<?xml version="1.0"?><COLLADA><library_visual_scenes>'
                 '<visual_scene id="s">' + '<node>' * 20000 + '</node>' * 20000 +
                 '</visual_scene></library_visual_scenes></COLLADA>')
DEEP_JSON_GLTF = write("deep_json.gltf", '{"asset":{"version":"2.0"},"extras":' + "[" * 100000 +
                       "]" * 100000 + "}")
CYCLE_GLTF = write("cycle.gltf", open(deep_gltf("cycle_src.gltf", 3)).read()
                   .replace('{"children":[1]}', '{"children":[1]}', 1)
                   .replace('{"mesh":0}', '{"mesh":0,"children":[1]}'))
DEEP_SCENE = write("deep_scene.json", '{"objects": ' + "[" * 5000 + "]" * 5000 + "}")
NESTED = "is nested deeper than 10000 levels"
case(H3, ["--model", DEEP_GLTF, "-o", OUT], "nonzero", "nested deeper than that", hard=True,
     keep=REF)
case(H3, ["--model", deep_gltf("deep500.gltf", 500), "--size", "16x16", "-o", OUT], 0, "wrote",
     absent=(), present=(OUT,), hard=True)
case(H3, ["--model", DEEP_DAE, "-o", OUT], "nonzero", NESTED, hard=True, keep=REF)
case(H3, ["--model", DEEP_JSON_GLTF, "-o", OUT], "nonzero", NESTED, hard=True, keep=REF)
case(H3, ["--model", CYCLE_GLTF, "-o", OUT], "nonzero", "not a tree", hard=True, keep=REF)
case(H2, ["--scene", DEEP_SCENE, "-o", OUT], 2, "expected JSON nested at most 1000 levels deep",
     hard=True, keep=REF)

# Counts a PLY/OFF header declares that the file cannot hold (assimp reserved
# them first: a 123-byte PLY took 4.7 GB and 10 s).
PLY_BOMB = write("bomb.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 400000000\n"
                 "property float x\nproperty float y\nproperty float z\nend_header\n")
OFF_BOMB = write("bomb.off", "OFF\n300000000 1 0\n0 0 0\n")
case(H3, ["--model", PLY_BOMB, "-o", OUT], "nonzero", "declares 400000000 elements", hard=True,
     keep=REF)
case(H3, ["--model", OFF_BOMB, "-o", OUT], "nonzero", "the file is truncated or corrupt",
     hard=True, keep=REF)
# A PLY element line without a count: assimp 5.2's header parser loops on it
# forever (found by fuzz_mesh); refused before assimp. Any other importer that
# hangs meets the import's time limit (RAS_MESH_IMPORT_SECONDS).
PLY_LOOP = write("loop.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                 "property float y\nproperty float z\nelement \x03OFF\n0 0 0\n1 0 0\n0 1 0\n")
case(H3, ["--model", PLY_LOOP, "-o", OUT], 2, "is not 'element NAME COUNT'", hard=True, keep=REF)
GRID_OBJ = write("grid.obj", "".join("v %d %d 0\n" % (i % 100, i // 100) for i in range(10000)) +
                 "".join("f %d %d %d\n" % (i + 1, i + 2, i + 101) for i in range(9800)))
case(H3, ["--model", GRID_OBJ, "-o", OUT], 2, "the importer did not finish", hard=True, keep=REF,
     env={"RAS_MESH_IMPORT_SECONDS": "0.000001"})

# ---- model guards by content, counts from the data's structure ----
import base64
import json
DEEP_TEXT = open(DEEP_GLTF).read()
for name in ("deep.vrm", "deep_gltf_without_extension"):  # a glb container name, no name
    case(H3, ["--model", write(name, DEEP_TEXT), "-o", OUT], "nonzero",
         f"{name}': its node tree is nested deeper than that", hard=True, keep=REF)
case(H3, ["--model", write("deep_dae_as.txt", open(DEEP_DAE).read()), "-o", OUT], "nonzero",
     NESTED, hard=True, keep=REF)
# A valid two-level glTF 1.0 (nodes keyed by id, children by id) renders,
# with its extension and without (was "not a tree").
TRI = base64.b64encode(struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)).decode()
GLTF1 = json.dumps({
    "asset": {"version": "1.0"}, "scene": "s", "scenes": {"s": {"nodes": ["root"]}},
    "nodes": {"root": {"children": ["leaf"]}, "leaf": {"meshes": ["m"]}},
    "meshes": {"m": {"primitives": [{"attributes": {"POSITION": "acc"}, "mode": 4}]}},
    "accessors": {"acc": {"bufferView": "bv", "byteOffset": 0, "byteStride": 12,
                          "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]}},
    "bufferViews": {"bv": {"buffer": "b", "byteOffset": 0, "byteLength": 36, "target": 34962}},
    "buffers": {"b": {"byteLength": 36, "type": "arraybuffer",
                      "uri": "data:application/octet-stream;base64," + TRI}}})
for name in ("gltf1.gltf", "gltf1_no_extension"):
    case(H3, ["--model", write(name, GLTF1), "--size", "16x16", "-o", OUT], 0, "wrote",
         absent=(), present=(OUT,), hard=True)
# A glb whose JSON chunk length says 0x7ffffff0 (assimp filled 2 GiB in 39 s),
# and one whose total length is more than the file.
JS = open(deep_gltf("glb_src.gltf", 3), "rb").read()
JS += b" " * (-len(JS) % 4)
case(H3, ["--model", write("lie.glb", b"glTF" + struct.pack("<III", 2, 20 + len(JS), 0x7ffffff0) +
                           b"JSON" + JS), "-o", OUT], "nonzero",
     "its JSON chunk's length says 2147483632 bytes, but the file has only", hard=True, keep=REF)
case(H3, ["--model", write("lie_total.vrm", b"glTF" + struct.pack("<III", 2, 1 << 30, len(JS)) +
                           b"JSON" + JS), "-o", OUT], "nonzero",
     "its header's total length says 1073741824 bytes", hard=True, keep=REF)
# External references stay inside the model's folder, as regular files.
SRC_GLTF = json.loads(open(deep_gltf("uri_src.gltf", 2)).read())
for k, (uri, said) in enumerate((("../../../../../../../../etc/passwd", "points outside the model's folder"),
                  ("/etc/passwd", "points outside the model's folder"),
                  ("file:///etc/passwd", "points outside the model's folder"),
                  ("fifo.obj", "is not a regular file"))):
    SRC_GLTF["buffers"][0]["uri"] = uri
    case(H3, ["--model", write(f"uri{k}.gltf", json.dumps(SRC_GLTF)), "-o", OUT], "nonzero",
         "buffers[0].uri '%s' %s" % (uri, said), hard=True, keep=REF)
    SRC_GLTF["buffers"][0]["uri"] = "data:application/octet-stream;base64," + TRI
os.symlink("/etc/passwd", path("link.bin"))
SRC_GLTF["buffers"][0]["uri"] = "link.bin"
case(H3, ["--model", write("uri_link.gltf", json.dumps(SRC_GLTF)), "-o", OUT], "nonzero",
     "buffers[0].uri 'link.bin' points outside the model's folder", hard=True, keep=REF)
# A PLY face of 10^9 indices in 189 bytes (std::bad_alloc, 16 GB under ASan),
# ASCII and binary, whatever the name.
PLY_HEAD = ("ply\nformat %s 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list %s int vertex_indices\nend_header\n")
PLY_LIST = write("list.ply", PLY_HEAD % ("ascii", "uchar") + "0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n")
PLY_LIST_BIN = write("list_bin.dat", (PLY_HEAD % ("binary_little_endian", "uint")).encode() +
                     struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<I4I", 10**9, 0, 1, 2, 0))
for bomb in (PLY_LIST, PLY_LIST_BIN):
    case(H3, ["--model", bomb, "-o", OUT], "nonzero",
         "a list in its PLY element 'face' declares 1000000000 items", hard=True, keep=REF)
case(H3, ["--model", write("list_ok.ply", PLY_HEAD % ("ascii", "uchar") +
                           "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "--size", "16x16", "-o", OUT], 0,
     "wrote", absent=(), present=(OUT,), hard=True)

# assimp's own words come last, after the project's (file, the format it is,
# what is wrong).
for name, text, said in (("bad_index.obj", "v 0 0 0\nf 1 2 9\n",
                          "it is an OBJ file, but a face names a vertex that does not exist"),
                         ("bad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n",
                          "it is an STL file, but not a complete one the importer can read")):
    case(H3, ["--model", write(name, text), "-o", OUT], "nonzero",
         f"could not read model '{path(name)}': {said}", hard=True, keep=REF)

# ---- every output all or nothing, every failure said ----
RO_OUT = write("readonly.png", open(REF, "rb").read())
os.chmod(RO_OUT, 0o444)
case(H2, ["--size", "16x16", "-o", RO_OUT], 2,
     "it is write-protected (mode 0444); expected a file you may replace — pass --force",
     absent=(), present=(RO_OUT,), hard=True)
RO_FORCED = write("readonly_forced.png", open(REF, "rb").read())
os.chmod(RO_FORCED, 0o444)
case(H2, ["--size", "8x8", "--force", "-o", RO_FORCED], 0, "wrote", absent=(), present=(RO_FORCED,),
     hard=True)
RO_DUMP = path("readonly-dump")
os.makedirs(RO_DUMP)
os.chmod(RO_DUMP, 0o555)
case(H3, ["-o", OUT, "--dump", RO_DUMP], 2, "--dump: the folder '%s' is not writable" % RO_DUMP,
     hard=True, keep=REF)
# A file-size limit during --dump: the buffers go to a temporary folder that
# is removed, the dump folder is not made, and -o stays as it was.
for prog in (H2, H3):
    case(prog, ["--size", "200x200", "-o", OUT, "--dump", path("fsize-dump-" + prog)], "nonzero",
         "File too large", hard=True, keep=REF, fsize=20000,
         absent=(path("fsize-dump-" + prog),))

# ---- nothing overwrites an input ----
DIFF_REF = write("cmp_diff.png", open(REF, "rb").read())  # what -o cmp.png's diff would be
for prog in (H2, H3):
    case(prog, ["--compare", "--reference", DIFF_REF, "--size", "16x16", "-o", path("cmp.png")],
         2, "which is the --reference image", absent=(path("cmp.png"),), present=(DIFF_REF,),
         hard=True)
IN_COPY = write("compare_input.png", open(REF, "rb").read())
case(C, ["--metric", "exact", "--diff", IN_COPY, REF, IN_COPY], 2,
     "would overwrite one of the images being compared", absent=(), present=(IN_COPY,),
     hard=True)
case(C, ["--metric", "exact", "--crop", os.path.join(WORK, ".", "ref.png"), REF, IN_COPY], 2,
     "would overwrite one of the images", absent=(), hard=True)

# ---- only what a program draws is loaded ----
# hw1 and hw2 draw flat colours: a scene's texture and height map (here a
# 16384² PNG bomb and a missing file) are never read; hw3 refuses the bomb.
MAP_SCENE = write("bomb_maps.json", '{"shader": "texture", "objects": [{"shape": "cube", '
                  '"material": {"texture": {"file": "%s"}, "height_map": {"file": '
                  '"no-such-map.png"}}}]}' % BOMB16K)
for prog in (H1, H2):
    case(prog, ["--scene", MAP_SCENE, "--size", "16x16", "-o", OUT], 0, "wrote", absent=(),
         present=(OUT,), hard=True)
case(H3, ["--scene", MAP_SCENE, "-o", OUT], "nonzero", OVER, hard=True, keep=REF)
case(H3, ["--scene", CORRUPT_TEXTURE_SCENE, "-o", OUT], 2, "corrupt.png")

# ---- raster101-compare --buffers: bad folders and files are errors ----
# A PFM whose header claims 100000² was handed to OpenCV, which left a
# /tmp/__opencv_temp.* file each run and said its raw error; a mistyped
# folder was called a mismatch (exit 1).
PFM_DIR = path("pfm-bomb")
os.makedirs(PFM_DIR)
with open(os.path.join(PFM_DIR, "depth.pfm"), "wb") as f:
    f.write(b"Pf\n100000 100000\n-1.0\n" + b"\x00" * 64)
GOOD_DUMP = path("dump-" + PROGRAMS[1 % len(PROGRAMS)])  # written by a good case above
CV_TMP = path("opencv-tmp")  # where OpenCV puts its temporary files (OPENCV_TEMP_PATH)
os.makedirs(CV_TMP)
case(C, ["--buffers", PFM_DIR, PFM_DIR], 2,
     "depth.pfm': its header says 100000x100000 with 1 channel, more than the 64 bytes",
     absent=(), hard=True, env={"OPENCV_TEMP_PATH": CV_TMP})
case(C, ["--buffers", path("no-such-dump"), PFM_DIR], 2,
     "--buffers: cannot open the folder '%s' (No such file or directory)" % path("no-such-dump"),
     absent=(), hard=True)
case(C, ["--buffers", PFM_DIR, REF], 2, "--buffers: '%s' is not a folder" % REF, absent=(),
     hard=True)

# ---- messages lead with the reason (issue 42 B9) -----------------------------
# A failed import names the format the file is and what is wrong in the
# project's words, assimp's text after it as detail.
BAD_INDEX_OBJ = write("bad-index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
case(H3, ["--model", BAD_INDEX_OBJ, "-o", OUT], 2,
     "it is an OBJ file, but a face names a vertex that does not exist")
case(H3, ["--model", write("storage.stl", b"\0" * 80 + struct.pack("<I", 1000) + b"\0" * 50),
          "-o", OUT], 2, "it is an STL file, but it is neither an ASCII STL")
case(H3, ["--model", write("v1.glb", b"glTF" + struct.pack("<II", 1, 100) + b"\0" * 88), "-o", OUT],
     2, "binary glTF (.glb) file of version 1, which the importer does not read")
# A path so long that the message would not hold it: cut in its middle, the
# reason after it whole.
LONG_DIR = path("/".join(["d" * 200] * 4))
os.makedirs(LONG_DIR)
LONG_OBJ = os.path.join(LONG_DIR, "m" * 150 + ".obj")
shutil.copyfile(BAD_INDEX_OBJ, LONG_OBJ)
case(H3, ["--model", LONG_OBJ, "-o", OUT], 2,
     "[...]" + "m" * 20)
case(H3, ["--model", LONG_OBJ, "-o", OUT], 2,
     "m.obj': it is an OBJ file, but a face names a vertex that does not exist; expected each "
     "'f' index within 1..N (or -1..-N) of the vertices before it; fix the face lines, or "
     "re-export the model [the importer said: OBJ: vertex index out of range]")
# Scenes: UTF-16 named as such (with or without its byte-order mark), a NUL
# escaped into a string refused, a URI where a file path goes refused.
CUBE_TEXT = '{"objects": [{"shape": "cube"}]}'
for enc in ("utf-16", "utf-16-le", "utf-16-be"):
    case(H3, ["--scene", write(f"scene-{enc}.json", CUBE_TEXT.encode(enc)), "-o", OUT], 2,
         "the scene is UTF-16")
case(H3, ["--scene", write("nul-escape.json", '{"objects": [{"shape": "cube\\u0000sphere"}]}'),
          "-o", OUT], 2, "nul-escape.json:1:29: expected a string without NUL characters")
case(H3, ["--scene", write("uri-texture.json",
                           '{"shader": "texture", "objects": [{"shape": "cube", "material": '
                           '{"texture": {"file": "file://%s"}}}]}' % REF), "-o", OUT], 2,
     'objects[0].material.texture.file: expected a file path')
case(H3, ["--scene", write("uri-model.json", '{"objects": [{"model": "file://%s"}]}' % OK_OBJ),
          "-o", OUT], 2, "got the URI")

with concurrent.futures.ThreadPoolExecutor(max_workers=max(2, os.cpu_count() or 2)) as pool:
    for result in pool.map(check, cases):
        if result:
            failures.append(result)
            print(result)

if os.listdir(CV_TMP):
    failures.append(f"FAIL: OpenCV temporary files left: {os.listdir(CV_TMP)}")
    print(failures[-1])

# No temporary dump folder (.NAME-XXXXXX) is left anywhere in WORK.
stray = [d for d in os.listdir(WORK) if d.startswith(".") and os.path.isdir(path(d))]
if stray:
    failures.append(f"FAIL: temporary dump folders left behind: {stray}")
    print(failures[-1])

# ---- an output never replaces an input (issue 42 B4), damaged inputs (B8) ----
# -o, --compare's difference images and --dump are refused, exit 2 before any
# drawing, when they are a file the run reads: by name, through a symbolic
# link, a hard link or another spelling; each input must come out unchanged.
NC = path("noclobber")
os.makedirs(NC)
def nc(name):
    return os.path.join(NC, name)
shutil.copyfile(REF, nc("tex.png"))
shutil.copyfile(REF, nc("ref.png"))
shutil.copyfile(OK_OBJ, nc("m.obj"))
os.symlink("tex.png", nc("tex-link.png"))
os.link(nc("tex.png"), nc("tex-hard.png"))
os.link(nc("m.obj"), nc("m-hard.png"))
os.link(nc("ref.png"), nc("ref-hard.png"))
os.symlink("no-such-file.png", nc("dangling.png"))
with open(nc("scene.json"), "w") as f:
    f.write('{"shader": "texture", "objects": [{"model": "m.obj", "material": '
            '{"texture": {"file": "tex.png"}}}]}')
os.makedirs(nc("dump"))
shutil.copyfile(REF, nc("dump/colour.png"))
NC_INPUTS = [nc(n) for n in ("tex.png", "ref.png", "m.obj", "scene.json", "dump/colour.png")]
NC_BYTES = {n: open(n, "rb").read() for n in NC_INPUTS}
NC_CASES = [
    (H3, ["--model", nc("m.obj"), "--texture", nc("tex.png"), "-o", nc("tex.png")],
     "is the --texture file"),
    (H3, ["--model", nc("m.obj"), "--texture", nc("tex.png"), "-o", nc("tex-link.png")],
     "is the --texture file"),
    (H3, ["--model", nc("m.obj"), "--texture", nc("tex.png"), "-o", nc("tex-hard.png")],
     "is the --texture file"),
    (H3, ["--model", nc("m.obj"), "--height", nc("tex.png"), "-o", nc("../noclobber/tex-hard.png")],
     "is the --height file"),
    (H3, ["--scene", nc("scene.json"), "-o", nc("tex-link.png")],
     "is the texture of object 0 of the scene"),
    (H3, ["--scene", nc("scene.json"), "-o", nc("m-hard.png")],
     "is the model of object 0 of the scene"),
    (H3, ["--model", nc("m.obj"), "--texture", nc("dump/colour.png"), "-o", nc("o1.png"),
          "--dump", nc("dump")], "--dump '%s' holds the --texture file" % nc("dump")),
    (H2, ["--compare", "--reference", nc("ref.png"), "--size", "16x16", "-o",
          nc("ref-hard.png")], "is the reference image --compare reads"),
    (H2, ["--size", "16x16", "-o", nc("dangling.png")],
     "is a symbolic link to a file that does not exist"),
    (H2, ["--size", "16x16", "-o", nc("x" * 300 + ".png")], "its name has a part of 304 bytes"),
]
for program, args, message in NC_CASES:
    code, _, err = run(program, args)
    what = f"{program} {' '.join(args)}"
    problems = [] if code == 2 else [f"exit {code}, expected 2"]
    if message not in err:
        problems.append(f"stderr lacks {message!r}")
    if "wrote" in err:
        problems.append("it drew and wrote before refusing")
    problems += [f"input {n} was changed" for n in NC_INPUTS if open(n, "rb").read() != NC_BYTES[n]]
    if [d for d in os.listdir(NC) if d.startswith(".")]:
        problems.append(f"left {[d for d in os.listdir(NC) if d.startswith('.')]}")
    if problems:
        failures.append(f"FAIL: {what}: {'; '.join(problems)}\n  stderr: {err.strip()[:600]}")
        print(failures[-1])
# The control: the same inputs with an output of its own are drawn.
code, _, err = run(H3, ["--scene", nc("scene.json"), "-o", nc("new.png")])
if code != 0 or not os.path.isfile(nc("new.png")):
    failures.append(f"FAIL: the no-clobber control run did not draw (exit {code}): {err[:300]}")
    print(failures[-1])

# A JPEG cut short: libjpeg only warns ("Premature end of JPEG file") and fills
# the rest with grey; refused like a truncated PNG, the file named, in every
# path that reads images.
CUT_JPG = write("cut.jpg", base[:len(base) // 2])
for program, args in ((H3, ["--model", OK_OBJ, "--texture", CUT_JPG, "-o", path("cut-out.png")]),
                      (H2, ["--compare", "--reference", CUT_JPG, "--size", "64x64", "-o",
                            path("cut-out.png")]),
                      (C, ["--metric", "exact", CUT_JPG, BASE_JPG]),
                      (C, ["--metric", "exact", BASE_JPG, CUT_JPG])):
    code, _, err = run(program, args)
    if code != 2 or "cut.jpg': it is cut short" not in err or os.path.exists(path("cut-out.png")):
        failures.append(f"FAIL: {program} {' '.join(args)}: exit {code}, expected 2 and "
                        f"\"cut.jpg': it is cut short\"; stderr: {err.strip()[:400]}")
        print(failures[-1])

# --buffers: a depth buffer all NaN or all +inf is named as such, never
# "differs ... (largest difference 0)".
run(H2, ["--size", "32x24", "-o", path("nf-a.png"), "--dump", path("nf-ref")])
for kind, value in (("nan", float("nan")), ("inf", float("inf"))):
    got = path("nf-" + kind)
    run(H2, ["--size", "32x24", "-o", path(f"nf-{kind}.png"), "--dump", got])
    with open(os.path.join(got, "depth.pfm"), "rb") as f:
        head = [f.readline() for _ in range(3)]
        count = len(f.read()) // 4
    with open(os.path.join(got, "depth.pfm"), "wb") as f:
        f.write(b"".join(head) + struct.pack(("<" if float(head[2]) < 0 else ">") + "f" * count,
                                             *([value] * count)))
    code, out, err = run(C, ["--buffers", path("nf-ref"), got])
    if code != 1 or "non-finite values (NaN/inf) in depth.pfm" not in out or \
            "largest difference 0" in out:
        failures.append(f"FAIL: --buffers with an all-{kind} depth: exit {code}, expected 1 and "
                        f"'non-finite values (NaN/inf) in depth.pfm'; stdout: {out.strip()[:400]}")
        print(failures[-1])

def stats_output(target):
    """--stats with stdout closed or on /dev/full: exit non-zero, said on stderr."""
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    cmd = [os.path.join(BIN, "hw2_rasterize_ref"), "--size", "16x16", "--stats", "-o",
           path(f"stats-{target}.png")]
    if target == "closed":
        cmd = ["sh", "-c", '"$0" "$@" >&-'] + cmd
        stdout = None
    else:
        stdout = open("/dev/full", "w")
    p = subprocess.run(cmd, stdout=stdout, stderr=subprocess.PIPE, text=True, env=env, cwd=WORK)
    want = "standard output, which is closed" if target == "closed" else \
        "--stats: could not write the counters to standard output (No space left on device)"
    if p.returncode == 0 or want not in p.stderr:
        return f"FAIL: --stats with stdout {target}: exit {p.returncode}, stderr {p.stderr!r}"
    return None
for target in ("closed", "full"):
    result = stats_output(target)
    if result:
        failures.append(result)
        print(result)

def stale_temporaries():
    """Temporaries a kill -9 left (.NAME-XXXXXX, older than the run) are removed
    by the next write into that folder; a fresh one, and other dotfiles, stay."""
    folder = path("stale")
    os.makedirs(folder)
    old = [os.path.join(folder, n) for n in (".out.png-AbC123", ".depth.pfm-x1y2z3")]
    keep = [os.path.join(folder, n) for n in (".notes-abcdef", ".out.png-AbC12")]
    for f in old + keep:
        open(f, "w").close()
        os.utime(f, (1e9, 1e9))  # 2001
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    p = subprocess.run([os.path.join(BIN, "hw2_rasterize_ref"), "--size", "8x8", "-o",
                        os.path.join(folder, "out.png")], capture_output=True, text=True, env=env)
    # and a --dump staging folder a kill -9 left beside DIR
    stale_dump = os.path.join(folder, ".dump-Qw3rTy")
    os.makedirs(stale_dump)
    open(os.path.join(stale_dump, "depth.pfm"), "w").close()
    os.utime(stale_dump, (1e9, 1e9))
    p2 = subprocess.run([os.path.join(BIN, "hw2_rasterize_ref"), "--size", "8x8", "-o",
                         os.path.join(folder, "out2.png"), "--dump", os.path.join(folder, "dump")],
                        capture_output=True, text=True, env=env)
    problems = [f"{f} was not removed" for f in old + [stale_dump] if os.path.exists(f)]
    if p2.returncode != 0:
        problems.append(f"--dump: exit {p2.returncode}: {p2.stderr}")
    problems += [f"{f} was removed" for f in keep if not os.path.exists(f)]
    if p.returncode != 0:
        problems.append(f"exit {p.returncode}: {p.stderr}")
    return f"FAIL: stale temporaries: {'; '.join(problems)}" if problems else None
result = stale_temporaries()
if result:
    failures.append(result)
    print(result)

# ---- a dump is one frame, all or nothing (issue 42 B7) ----------------------
def dump_env():
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    return env

def dump_run(args, umask=None, **kw):
    return subprocess.run([os.path.join(BIN, H2)] + args, capture_output=True, text=True,
                          env=dump_env(), cwd=WORK, errors="replace",
                          preexec_fn=(lambda: os.umask(umask)) if umask is not None else None, **kw)

def stages_of(folder, name):
    return glob.glob(os.path.join(glob.escape(folder), f".{name}-*"))

def dump_folder_mode():
    """A new dump folder has a plain mkdir's mode (0777 & ~umask), not mkdtemp's 0700."""
    problems = []
    for umask, want in ((0o022, 0o755), (0o002, 0o775)):
        d = path(f"dump-mode-{umask:o}")
        p = dump_run(["--size", "16x16", "-o", path(f"dump-mode-{umask:o}.png"), "--dump", d], umask)
        got = os.stat(d).st_mode & 0o7777 if os.path.isdir(d) else None
        if p.returncode != 0 or got != want:
            problems.append(f"umask {umask:04o}: exit {p.returncode}, mode "
                            f"{'none' if got is None else oct(got)}, expected {oct(want)}")
    return problems

def dump_replaces_the_set():
    """A second frame into a folder replaces the first's files as a set: the
    first frame's coverage and sample_colour (only --aa makes them) go, a file
    that is not a dump file stays, and --buffers finds one frame."""
    d = path("dump-set")
    problems = []
    dump_run(["--size", "24x16", "--aa", "ssaa", "--samples", "4", "-o", path("dump-set.png"),
              "--dump", d])
    open(os.path.join(d, "notes.txt"), "w").close()
    p = dump_run(["--size", "20x12", "-o", path("dump-set.png"), "--dump", d])
    left = sorted(n for n in os.listdir(d) if n.startswith(("coverage", "sample_colour")))
    if p.returncode != 0 or left:
        problems.append(f"the older frame's files stayed: {left} (exit {p.returncode})")
    if not os.path.exists(os.path.join(d, "notes.txt")):
        problems.append("notes.txt, not a dump file, was removed")
    code, out, err = run(C, ["--buffers", d, d])
    if code != 0:
        problems.append(f"--buffers of the folder with itself: exit {code}: {err.strip()[:300]}")
    return problems

def buffers_refuse_two_frames():
    """--buffers refuses a folder holding two frames' files (a sidecar of
    another frame; a .pfm of another size than its sidecar says), exit 2."""
    problems = []
    a, b = path("dump-fa"), path("dump-fb")
    dump_run(["--size", "24x16", "-o", path("dump-fa.png"), "--dump", a])
    dump_run(["--size", "30x20", "-o", path("dump-fb.png"), "--dump", b])
    mixed = path("dump-mixed-json")
    shutil.copytree(a, mixed)
    shutil.copyfile(os.path.join(b, "overdraw.json"), os.path.join(mixed, "overdraw.json"))
    stale_pfm = path("dump-mixed-pfm")
    shutil.copytree(a, stale_pfm)
    shutil.copyfile(os.path.join(b, "depth.pfm"), os.path.join(stale_pfm, "depth.pfm"))
    lone_pfm = path("dump-lone-pfm")
    shutil.copytree(a, lone_pfm)
    os.unlink(os.path.join(lone_pfm, "overdraw.json"))
    for got in (mixed, stale_pfm, lone_pfm):
        for pair in ((a, got), (got, a)):
            code, out, err = run(C, ["--buffers", *pair])
            if code != 2 or "holds files of two frames" not in err:
                problems.append(f"--buffers {pair[0]} {pair[1]}: exit {code}, expected 2 and "
                                f"'holds files of two frames'; stderr {err.strip()[:300]!r}")
    return problems

def dump_held_in_fsync(name, extra=()):
    """hw2 dumping into WORK/NAME with each fsync held 3 s by strace, returned
    once its stage folder holds a file: (strace process, the program's pid), or
    None when the dump could not be caught in the act."""
    import time
    p = subprocess.Popen(["strace", "-f", "-o", os.devnull, "-e", "trace=fsync", "-e",
                          "inject=fsync:delay_exit=3000000", os.path.join(BIN, H2), "--size",
                          "64x48", "-o", path(name + ".png"), "--dump", path(name), *extra],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=dump_env(),
                         cwd=WORK)
    deadline = time.time() + 15
    while time.time() < deadline and p.poll() is None:
        time.sleep(0.05)
        if any(os.listdir(s) for s in stages_of(WORK, name) if os.path.isdir(s)):
            child = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True,
                                   text=True).stdout.split()
            if child:
                return p, int(child[0])
    p.kill()
    p.wait()
    return None

def dump_signals():
    """SIGINT, SIGTERM, SIGHUP mid-dump: the process dies of the signal, the
    stage folder is gone and DIR is not made. A kill -9 leaves the stage (no
    handler runs) and the very next dump there removes it: its owner's lock is
    free, whatever the clock says."""
    import signal
    problems = []
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGKILL):
        name = f"dump-sig{int(sig)}"
        held = dump_held_in_fsync(name)
        if not held:
            return [f"SKIP: {sig.name}: the dump could not be caught in the act"]
        p, pid = held
        os.kill(pid, sig)
        p.wait(timeout=20)
        left = stages_of(WORK, name)
        if sig != signal.SIGKILL:
            if left or os.path.exists(path(name)):
                problems.append(f"{sig.name} mid-dump left {left or path(name)}")
            continue
        if not left:
            return [f"SKIP: kill -9 left no stage to sweep"]
        q = dump_run(["--size", "16x16", "-o", path(name + ".png"), "--dump", path(name)])
        if q.returncode != 0 or stages_of(WORK, name):
            problems.append(f"the stage a kill -9 left was not swept by the next dump there: "
                            f"{stages_of(WORK, name)} (exit {q.returncode}: {q.stderr.strip()[:200]})")
    return problems

def dumps_at_once():
    """Two dumps of different sizes into one folder at the same time, six
    times: each time the folder holds one frame (--buffers of it with itself
    passes, every sidecar names one frame) and no stage is left."""
    import json as _json
    problems = []
    d = path("dump-race")
    for r in range(6):
        ps = [subprocess.Popen([os.path.join(BIN, H2), "--size", size, "--aa", "ssaa", "-o",
                                path(f"dump-race{size}.png"), "--dump", d], env=dump_env(), cwd=WORK,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
              for size in ("160x120", "200x150")]
        codes = [p.wait(timeout=120) for p in ps]
        frames = {_json.load(open(f)).get("frame") for f in glob.glob(os.path.join(d, "*.json"))}
        code, _, err = run(C, ["--buffers", d, d])
        if codes != [0, 0] or len(frames) != 1 or code != 0 or stages_of(WORK, "dump-race"):
            problems.append(f"round {r}: exits {codes}, {len(frames)} frames, --buffers exit "
                            f"{code} {err.strip()[:200]!r}, stages {stages_of(WORK, 'dump-race')}")
    return problems

def dump_names_before_rendering():
    """A --dump name the file system cannot hold (a 300-byte part) or a link to
    nothing is refused before any drawing, exit 2, -o not written."""
    problems = []
    os.symlink("no-such-folder", path("dump-dangling"))
    for name, said in (("y" * 300, "is 300 bytes; expected at most 255"),
                       ("dump-dangling", "is a symbolic link to something that does not exist")):
        out = path("dump-name.png")
        p = dump_run(["--size", "16x16", "-o", out, "--dump", path(name)])
        if p.returncode != 2 or said not in p.stderr or os.path.exists(out):
            problems.append(f"--dump {name[:40]}: exit {p.returncode}, expected 2 and {said!r} "
                            f"before -o was written; stderr {p.stderr.strip()[:300]!r}")
    return problems

DUMP_CHECKS = [dump_names_before_rendering, dump_folder_mode, dump_replaces_the_set, buffers_refuse_two_frames, dumps_at_once]
if shutil.which("strace") and shutil.which("pgrep") and not SANITIZED:
    DUMP_CHECKS.append(dump_signals)
for check_dump in DUMP_CHECKS:
    for problem in check_dump():
        print(f"{'' if problem.startswith('SKIP') else 'FAIL: '}{check_dump.__name__}: {problem}")
        if not problem.startswith("SKIP"):
            failures.append(f"FAIL: {check_dump.__name__}: {problem}")

def signal_during_write(sig):
    """SIGINT/SIGTERM while the temporary file exists (the write held in fsync
    by strace's fault injection): the process dies of the signal, the old
    output stays byte-identical and the temporary file is gone."""
    import signal
    import time
    out = path(f"signal{sig}.png")
    shutil.copyfile(REF, out)
    before = open(out, "rb").read()
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    p = subprocess.Popen(["strace", "-f", "-o", os.devnull, "-e", "trace=fsync", "-e",
                          "inject=fsync:delay_exit=3000000",
                          os.path.join(BIN, "hw2_rasterize_ref"), "-o", out],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, cwd=WORK)
    temps, deadline = [], time.time() + 15
    while not temps and time.time() < deadline and p.poll() is None:
        time.sleep(0.05)
        temps = glob.glob(os.path.join(glob.escape(WORK), f".signal{sig}.png-*"))
    child = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
    if not temps or not child:
        p.kill()
        p.wait()
        return f"SKIP: signal {sig}: the write could not be caught in the act"
    os.kill(int(child[0]), sig)
    p.wait(timeout=20)
    problems = []
    if glob.glob(os.path.join(glob.escape(WORK), f".signal{sig}.png-*")):
        problems.append("the temporary file was left behind")
    if open(out, "rb").read() != before:
        problems.append(f"{out} was changed")
    if problems:
        return f"FAIL: signal {sig} during the write: {'; '.join(problems)}"
    print(f"signal {sig} during the write: exit {p.returncode}, old file intact, no temporary "
          "file")
    return None

# Needs strace and ptrace (not under ASan: too slow to time).
if shutil.which("strace") and shutil.which("pgrep") and not SANITIZED:
    import signal as _signal
    for sig in (_signal.SIGINT, _signal.SIGTERM):
        result = signal_during_write(sig)
        if result and result.startswith("FAIL"):
            failures.append(result)
        if result:
            print(result)
print(f"{len(cases)} cases, {len(failures)} failed")
sys.exit(1 if failures else 0)
