#!/usr/bin/env python3
"""Drives aslam-viewer's page in headless Chromium through chromedriver (WebDriver over HTTP on
loopback), for tests/viewer_browser_test.sh. Standard library only.

  viewer_browser.py check VIEWER_PORT DRIVER_PORT FIXTURE CONTROL_LOG_TO_WAIT SCREENSHOT
      loads the page, waits for the fixture's replay to be shown, then prints one line per
      check as 'ok: NAME' or 'FAILED: NAME (why)'.
  viewer_browser.py screenshot VIEWER_PORT DRIVER_PORT FILE
      loads the page, lets it take in the state for a few seconds, saves a screenshot.
  viewer_browser.py lcm-log-summary LOG
      prints each event as 'CHANNEL SIZE FIRST_BYTES_HEX' (to check what the page published).
"""

import base64
import json
import struct
import sys
import time
import urllib.error
import urllib.request

LCM_SYNC = 0xEDA1DA01


def lcm_log_events(path):
    """(channel, data) of each event of an lcm-logger file (LCM's documented log format)."""
    with open(path, "rb") as f:
        blob = f.read()
    events, at = [], 0
    while at + 28 <= len(blob):
        sync, _number, _utime, channel_len, data_len = struct.unpack_from(">IqqII", blob, at)
        if sync != LCM_SYNC:
            raise ValueError(f"{path}: no sync word at byte {at}")
        at += 28
        channel = blob[at:at + channel_len].decode()
        at += channel_len
        events.append((channel, blob[at:at + data_len]))
        at += data_len
    return events


def last_frontier_count(fixture):
    """num_frontiers of the last FRONTIERS message: after the 8-byte fingerprint, utime and
    map_revision (int64 each) comes num_frontiers (int32), big-endian as LCM encodes."""
    counts = [struct.unpack_from(">i", data, 24)[0]
              for channel, data in lcm_log_events(fixture) if channel == "FRONTIERS"]
    if not counts:
        raise ValueError(f"{fixture}: no FRONTIERS message")
    return counts[-1]


class WebDriver:
    def __init__(self, port):
        self.base = f"http://127.0.0.1:{port}"
        caps = {"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {
                "binary": "/usr/bin/chromium",
                "args": ["--headless=new", "--no-sandbox", "--disable-gpu",
                         "--disable-dev-shm-usage", "--window-size=1280,800",
                         "--no-first-run", "--disable-extensions"]}}}}
        self.session = self.call("POST", "/session", caps)["sessionId"]

    def call(self, method, path, body=None):
        data = json.dumps(body).encode() if body is not None else None
        request = urllib.request.Request(self.base + path, data=data, method=method,
                                         headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(request, timeout=60) as response:
                return json.loads(response.read())["value"]
        except urllib.error.HTTPError as e:
            raise RuntimeError(f"{method} {path}: {e.code} {e.read()[:500]!r}") from None

    def s(self, path):
        return f"/session/{self.session}{path}"

    def go(self, url):
        self.call("POST", self.s("/url"), {"url": url})

    def js(self, script, *args):
        return self.call("POST", self.s("/execute/sync"), {"script": script, "args": list(args)})

    def click(self, css):
        element = self.call("POST", self.s("/element"), {"using": "css selector", "value": css})
        element_id = next(iter(element.values()))
        self.call("POST", self.s(f"/element/{element_id}/click"), {})

    def screenshot(self, path):
        with open(path, "wb") as f:
            f.write(base64.b64decode(self.call("GET", self.s("/screenshot"))))

    def quit(self):
        try:
            self.call("DELETE", self.s(""))
        except Exception:  # the browser may be gone already
            pass


def wait_until(what, timeout_s=20.0):
    deadline = time.time() + timeout_s
    while time.time() < deadline:
        value = what()
        if value:
            return value
        time.sleep(0.2)
    return what()


def check(viewer_port, driver_port, fixture, screenshot):
    results = []

    def report(name, ok, why=""):
        results.append(ok)
        print(f"ok: {name}" if ok else f"FAILED: {name} ({why})", flush=True)

    expected_rows = last_frontier_count(fixture)
    driver = WebDriver(driver_port)
    try:
        driver.go(f"http://127.0.0.1:{viewer_port}/")
        state = "return window.aslamViewer || null"
        report("the page connects and applies updates",
               bool(wait_until(lambda: (driver.js(state) or {}).get("frames", 0) > 0)),
               f"window.aslamViewer = {driver.js(state)}")
        # The replay ends with the fixture's last FRONTIERS: wait for the table to settle on it.
        rows = "return document.querySelectorAll('#frontier-table tbody tr').length"
        wait_until(lambda: driver.js(rows) == expected_rows, timeout_s=40.0)
        got = driver.js(rows)
        report(f"the frontier table has a row per frontier of the last FRONTIERS "
               f"({expected_rows})", got == expected_rows, f"{got} rows")
        # Not blank: the map, graph and frontiers give the canvas many colours.
        colours = driver.js("""
            const c = document.getElementById('map-canvas');
            const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
            const seen = new Set();
            for (let i = 0; i < d.length; i += 4 * 7) seen.add((d[i] << 16) | (d[i+1] << 8) | d[i+2]);
            return seen.size;""")
        report("the map canvas is not blank", colours >= 4, f"{colours} colours")
        driver.click("#btn-pause")
        result = wait_until(lambda: "ok" in (driver.js(
            "const e = document.getElementById('control-result'); "
            "return e ? e.textContent : ''") or ""), timeout_s=10.0)
        report("a click on pause is answered", bool(result), "no control result shown")
        driver.screenshot(screenshot)
        print(f"screenshot: {screenshot}", flush=True)
    finally:
        driver.quit()
    return 0 if all(results) else 1


def screenshot(viewer_port, driver_port, path, width=1400, height=820):
    driver = WebDriver(driver_port)
    try:
        driver.call("POST", driver.s("/window/rect"), {"width": width, "height": height})
        driver.go(f"http://127.0.0.1:{viewer_port}/")
        wait_until(lambda: (driver.js("return window.aslamViewer || null") or {}).get("frames", 0)
                   > 2)
        time.sleep(3.0)
        driver.screenshot(path)
    finally:
        driver.quit()
    return 0


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "lcm-log-summary":
        for channel, data in lcm_log_events(sys.argv[2]):
            print(channel, len(data), data[:24].hex())
        return 0
    if len(sys.argv) == 5 and sys.argv[1] == "screenshot":
        return screenshot(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4])
    if len(sys.argv) == 6 and sys.argv[1] == "check":
        return check(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
