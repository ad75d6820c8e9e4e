#!/usr/bin/env python3
"""class-view-timing.py — how long Chromium takes to render a page, measured
by the page's own clock (tests/grading/class-view-test --bench): Chromium is
driven over its DevTools pipe (--remote-debugging-pipe; no network, no port),
the page is loaded, and the navigation's load end and first contentful paint
are read from the Performance API (the page's own policy allows no script:
DevTools' evaluation is not the page's). Chromium's start is not counted.

    class-view-timing.py CHROMIUM PROFILE_DIR FILE.html   -> "load_ms fcp_ms"
"""
import json, os, subprocess, sys


def to_fds_3_4(r, w):
    # through fresh copies: dup2 onto the same number would keep os.pipe's
    # close-on-exec
    r, w = os.dup(r), os.dup(w)
    os.dup2(r, 3)
    os.dup2(w, 4)


def main():
    chromium, profile, page = sys.argv[1:4]
    to_chrome_r, to_chrome_w = os.pipe()
    from_chrome_r, from_chrome_w = os.pipe()
    proc = subprocess.Popen(
        [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
         "--proxy-server=127.0.0.1:9", "--user-data-dir=" + profile,
         "--remote-debugging-pipe", "about:blank"],
        close_fds=False, stdout=subprocess.DEVNULL,
        stderr=open(os.environ.get("CLASS_VIEW_CHROMIUM_LOG", os.devnull), "ab"),
        # Chromium reads the pipe on fd 3 and writes on fd 4 (dup2's copies are
        # inherited; os.pipe's own ends close at exec)
        preexec_fn=lambda: to_fds_3_4(to_chrome_r, from_chrome_w))
    os.close(to_chrome_r); os.close(from_chrome_w)
    out, buf, ids = os.fdopen(to_chrome_w, "wb", 0), b"", [0]
    inp = os.fdopen(from_chrome_r, "rb", 0)

    def messages():
        nonlocal buf
        while True:
            while b"\0" in buf:
                msg, buf = buf.split(b"\0", 1)
                yield json.loads(msg)
            chunk = inp.read(65536)
            if not chunk:
                raise SystemExit("class-view-timing: Chromium closed its pipe")
            buf += chunk
    stream = messages()

    def call(method, params=None, session=None, until=None):
        ids[0] += 1
        m = {"id": ids[0], "method": method, "params": params or {}}
        if session: m["sessionId"] = session
        out.write(json.dumps(m).encode() + b"\0")
        result = None
        for msg in stream:
            if msg.get("id") == ids[0]:
                if "error" in msg: raise SystemExit(f"class-view-timing: {method}: {msg['error']}")
                result = msg.get("result", {})
                if not until: return result
            elif until and msg.get("method") == until and result is not None:
                return result

    target = call("Target.createTarget", {"url": "about:blank"})["targetId"]
    session = call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
    call("Page.enable", session=session)
    call("Page.navigate", {"url": "file://" + os.path.abspath(page)}, session, until="Page.loadEventFired")
    expr = ("document.body.offsetHeight, JSON.stringify([performance.getEntriesByType('navigation')[0].loadEventEnd,"
            " (performance.getEntriesByName('first-contentful-paint')[0] || {startTime: -1}).startTime])")
    r = call("Runtime.evaluate", {"expression": expr, "returnByValue": True}, session)
    load, fcp = json.loads(r["result"]["value"])
    print(f"{load:.0f} {fcp:.0f}")
    try: call("Browser.close")
    except SystemExit: pass
    proc.wait(timeout=30)


main()
