#!/usr/bin/python3
"""The bridge's dashboard in a real headless Chromium (docs/dashboard.md).

Starts mosquitto on a free loopback port, nclink-sim (the simulated mill) and
nclink-bridge, then drives /dashboard with Selenium: the page loads, the mill
shows online, a live value changes on screen, a Set sent from the page is what
an NC-Link Query (`nclink query`) then reads, a method another application
calls (`nclink call`) shows in the panel of method runs, and /metrics is valid. With
--screenshot FILE it saves the page. Exit 77 (skipped, with the reason) when
Chromium, chromedriver or python3-selenium is missing.

usage: dashboard_browser_test.py BIN_DIR [--screenshot FILE]
"""
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

DEVICE = "nclink-sim-mill-01"


def skip(reason):
    print("skipped: " + reason)
    sys.exit(77)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def eventually(what, predicate, timeout=60.0):
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        try:
            last = predicate()
            if last:
                return last
        except Exception as e:  # the page or a server not there yet
            last = e
        time.sleep(0.2)
    raise AssertionError("timed out waiting for " + what + " (last: " + repr(last) + ")")


def main():
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    bin_dir = sys.argv[1]
    screenshot = sys.argv[sys.argv.index("--screenshot") + 1] if "--screenshot" in sys.argv else None
    try:
        from selenium import webdriver
        from selenium.webdriver.common.by import By
    except ImportError:
        skip("python3-selenium is not installed (NCLINK_WITH_BROWSER=1 tools/install-deps.sh)")
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    driver_path = shutil.which("chromedriver")
    if not chromium or not driver_path:
        skip("chromium or chromium-driver is not installed (NCLINK_WITH_BROWSER=1 tools/install-deps.sh)")
    mosquitto = next((p for p in ("/usr/sbin/mosquitto", "/usr/bin/mosquitto") if os.access(p, os.X_OK)), None)
    if not mosquitto:
        skip("mosquitto is not installed")
    for program in ("nclink-sim", "nclink-bridge", "nclink"):
        if not os.access(os.path.join(bin_dir, program), os.X_OK):
            skip(program + " is not built")

    work = tempfile.mkdtemp(prefix="nclink-dashboard-")
    processes = []
    browser = None

    def start(name, argv):
        log = open(os.path.join(work, name + ".log"), "w")
        processes.append((name, subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT)))

    try:
        mqtt_port, http_port = free_port(), free_port()
        with open(os.path.join(work, "mosquitto.conf"), "w") as conf:
            conf.write("listener %d 127.0.0.1\nallow_anonymous true\npersistence false\n" % mqtt_port)
        start("mosquitto", [mosquitto, "-c", os.path.join(work, "mosquitto.conf")])
        broker = "tcp://127.0.0.1:%d" % mqtt_port
        eventually("mosquitto", lambda: socket.create_connection(("127.0.0.1", mqtt_port), 1).close() or True)
        start("nclink-sim", [os.path.join(bin_dir, "nclink-sim"), "--broker", broker, "--persistence", os.path.join(work, "sim")])
        start("nclink-bridge", [os.path.join(bin_dir, "nclink-bridge"), "--broker", broker, "--device", DEVICE,
                                "--http", "127.0.0.1:%d" % http_port, "--shdr", "off"])
        base = "http://127.0.0.1:%d" % http_port

        def model_known():
            with urllib.request.urlopen(base + "/nclink/v1/devices/" + DEVICE + "/model", timeout=2) as r:
                return r.status == 200
        eventually("the bridge to know the mill's model", model_known, 90)

        options = webdriver.ChromeOptions()
        options.binary_location = chromium
        for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
                         "--window-size=1400,1000"):
            options.add_argument(argument)
        from selenium.webdriver.chrome.service import Service
        browser = webdriver.Chrome(service=Service(driver_path), options=options)
        browser.set_page_load_timeout(60)
        browser.get(base + "/dashboard")
        assert browser.title == "nclink dashboard", browser.title

        # The fleet: the mill, online.
        row = '#fleet tr[data-dev="%s"]' % DEVICE
        eventually("the mill online in the fleet",
                   lambda: browser.find_element(By.CSS_SELECTOR, row + " td.state-online").text == "online")
        # Its model tree with live values: an axis position that moves.
        cell = lambda item: browser.find_element(By.ID, "v-" + item)
        first = eventually("a value of x_position", lambda: cell("x_position").text not in ("", "—") and cell("x_position").text)
        eventually("x_position to change on screen", lambda: cell("x_position").text not in (first, "", "—"))
        # The health line came from /nclink/v1/health.
        eventually("the bridge's health", lambda: "devices online" in browser.find_element(By.ID, "health").text)
        # A sample channel plotted: its legend names plotted items.
        eventually("a plotted sample channel", lambda: browser.find_element(By.ID, "legend").text.strip() != "")

        # A Set from the page...
        old = subprocess.run([os.path.join(bin_dir, "nclink"), "query", "--broker", broker, "--device", DEVICE,
                              "spindle_override"], capture_output=True, text=True, timeout=30).stdout.strip()
        target = 73
        form = browser.find_element(By.CSS_SELECTOR, 'form[data-set="spindle_override"]')
        field = form.find_element(By.CSS_SELECTOR, "input")
        field.clear()
        field.send_keys(str(target))
        form.find_element(By.CSS_SELECTOR, "button").click()
        eventually("the Set's answer in the page's log",
                   lambda: "Set spindle_override = %d: OK" % target in browser.find_element(By.ID, "log").text)

        # ... is what NC-Link Query reads now.
        def queried():
            run = subprocess.run([os.path.join(bin_dir, "nclink"), "query", "--broker", broker, "--device", DEVICE,
                                  "spindle_override"], capture_output=True, text=True, timeout=30)
            return run.returncode == 0 and ("spindle_override = %d" % target) in run.stdout and run.stdout
        print("nclink query after the Set: " + eventually("nclink query to read the Set value", queried).strip()
              + " (before: " + old + ")")
        eventually("the new value on screen", lambda: cell("spindle_override").text == str(target))

        # Another application calls a method: the run shows up, live, in the
        # page's panel of method runs, with its caller and result.
        call = subprocess.run([os.path.join(bin_dir, "nclink"), "call", "--broker", broker, "--client-id", "dash-operator",
                               "--no-progress", DEVICE, "cycle_start", "{}"], capture_output=True, text=True, timeout=60)
        assert call.returncode == 0, call.stdout + call.stderr
        run_row = '#runs tr[data-method="cycle_start"][data-ex="dash-operator"]'
        eventually("the method run in the page's panel",
                   lambda: browser.find_element(By.CSS_SELECTOR, run_row + " td.result").text.startswith("finished"))
        print("method run on the page: " + browser.find_element(By.CSS_SELECTOR, run_row).text)

        # /metrics of the same server, as Prometheus scrapes it.
        with urllib.request.urlopen(base + "/metrics", timeout=5) as r:
            metrics = r.read().decode()
        assert 'nclink_bridge_devices{state="online"} 1' in metrics, metrics
        assert 'route="/nclink/v1/devices/{dev}/set"' in metrics, metrics
        if shutil.which("promtool"):
            check = subprocess.run(["promtool", "check", "metrics"], input=metrics, capture_output=True, text=True)
            assert check.returncode == 0, check.stdout + check.stderr

        if screenshot:
            time.sleep(3)  # a few seconds of plot
            # Every panel on one picture, down to the method runs and events.
            browser.execute_script("document.body.style.zoom = '0.75'")
            height = browser.execute_script("return Math.ceil(document.documentElement.scrollHeight * 0.75)")
            browser.set_window_size(1400, max(1000, int(height) + 120))
            time.sleep(1)
            browser.save_screenshot(screenshot)
            print("screenshot: " + screenshot)
        print("dashboard: page, fleet, live value, Set and Query, method run, metrics: all passed")
        return 0
    except Exception:
        for name, _ in processes:
            path = os.path.join(work, name + ".log")
            print("---- " + name + " log (last lines)")
            print("".join(open(path, errors="replace").readlines()[-30:]))
        if browser:
            try:
                print("---- page text\n" + browser.find_element(By.TAG_NAME, "body").text[:3000])
                print("---- browser console")
                for entry in browser.get_log("browser"):
                    print(entry)
            except Exception as e:
                print("(no page: %r)" % e)
        raise
    finally:
        if browser:
            browser.quit()
        for _, process in reversed(processes):
            process.terminate()
            try:
                process.wait(10)
            except subprocess.TimeoutExpired:
                process.kill()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
