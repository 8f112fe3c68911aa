#!/usr/bin/env python3
"""ctest deploy_nspawn_installation (label deploy): a whole installation provisioned for real.

A hub and three camera nodes are Debian bookworm machines booted with systemd in systemd-nspawn
containers (root made here with debootstrap from Debian's packages plus the packages' own
dependencies, cached in the build tree and shared read-only through overlayfs), on a bridge in a
network namespace this test creates (nothing else reaches it; the host side plays the operator's
machine). deploy/provision installs the packages CPack builds from this build, writes the configs,
the keys and chrony's configuration over real SSH from an inventory; the nodes replay frames
rendered by `mocap-hub sim render` under systemd; serve captures a session, which is reconstructed
on the hub and compared with the truth. Then: a second provision run changes and restarts nothing,
and an upgrade to a package whose node cannot start is rolled back.

Test-only adaptation: the containers share the host's clock, so chronyd runs with -x (it measures
and serves time but never sets the clock) through a drop-in the test adds; provisioning itself
does not know about it.

usage: deploy_test.py BIN_DIR BUILD_DIR WORK_DIR
Every wait is bounded; machines, mounts and the namespace are removed even on failure.
"""
import hashlib
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import unittest

BIN, BUILD, WORK = (os.path.abspath(a) for a in sys.argv[1:4]) if len(sys.argv) >= 4 else (None,) * 3
SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CACHE = os.path.join(BUILD or "", "tests", "deploy-cache")
SUITE, MIRROR = "bookworm", "http://deb.debian.org/debian"
# What every machine needs besides the packages' own dependencies: boot, network, SSH, time.
BASE_PACKAGES = ["systemd", "systemd-sysv", "dbus", "openssh-server", "chrony", "iproute2", "udev"]
NS = f"mocapdeploy{os.getpid()}"
SUBNET = "10.77.0"
OPERATOR = f"{SUBNET}.254"
HUB = ("hub", f"{SUBNET}.1")
NODES = [(i, f"node{i}", f"{SUBNET}.{10 + i}") for i in (1, 2, 3)]
RATE, FRAMES = 60, 120


def run(cmd, timeout=120, check=True, **kw):
    """A command with a time limit; its output (text) returned; a failure shows what it said."""
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, **kw)
    if check and p.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)} -> {p.returncode}\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}")
    return p


def in_ns(cmd):
    # nsenter, not `ip netns exec`: that one mounts a sysfs of its own without the cgroup
    # hierarchies nspawn needs to see.
    return ["nsenter", f"--net=/run/netns/{NS}"] + cmd


def log(msg):
    print(f"deploy: {msg}", file=sys.stderr, flush=True)


def wait_for(what, probe, timeout):
    deadline = time.monotonic() + timeout
    while True:
        value = probe()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.5)


def build_packages(out):
    """The .deb files from this build, as `cmake --build build --target package` makes them."""
    shutil.rmtree(out, ignore_errors=True)
    run(["cpack", "-G", "DEB", "--config", os.path.join(BUILD, "CPackConfig.cmake"), "-B", out], timeout=300)
    debs = {f.split("_")[0]: os.path.join(out, f) for f in os.listdir(out) if f.endswith(".deb")}
    assert set(debs) == {"mocap-node", "mocap-hub"}, f"cpack made {sorted(debs)}"
    return debs


def rootfs(debs):
    """The machines' root: debootstrap + the packages' dependencies, cached by what it holds
    (a new dependency of the packages makes a new root; the previous one is removed)."""
    # Depends and Recommends: apt installs both, and the machines have no mirror to fetch them.
    depends = ", ".join(run(["dpkg-deb", "-f", debs[p], field]).stdout.strip()
                        for p in sorted(debs) for field in ("Depends", "Recommends"))
    key = hashlib.sha256(f"{SUITE} {MIRROR} {BASE_PACKAGES} {depends}".encode()).hexdigest()[:16]
    root = os.path.join(CACHE, f"rootfs-{key}")
    if os.path.isfile(os.path.join(root, ".complete")):
        log(f"root file system cached: {root}")
        return root
    os.makedirs(CACHE, exist_ok=True)
    for old in os.listdir(CACHE):
        shutil.rmtree(os.path.join(CACHE, old), ignore_errors=True)
    tmp = root + ".tmp"
    start = time.monotonic()
    log(f"debootstrap {SUITE} into {tmp} (cold cache)")
    run(["debootstrap", "--variant=minbase", "--include=" + ",".join(BASE_PACKAGES), SUITE, tmp, MIRROR],
        timeout=900)
    # The packages' library dependencies, as apt would resolve them on a machine with a mirror
    # (the machines themselves have no route to one).
    run(["chroot", tmp, "apt-get", "satisfy", "-y", "-q", "--no-install-recommends", depends],
        timeout=900, env={**os.environ, "DEBIAN_FRONTEND": "noninteractive"})
    run(["chroot", tmp, "apt-get", "clean"])
    run(["chroot", tmp, "systemctl", "enable", "systemd-networkd"])
    # Every machine gets its own SSH host keys and machine id at first boot.
    for f in os.listdir(os.path.join(tmp, "etc", "ssh")):
        if f.startswith("ssh_host_"):
            os.remove(os.path.join(tmp, "etc", "ssh", f))
    open(os.path.join(tmp, "etc", "machine-id"), "w").close()
    open(os.path.join(tmp, ".complete"), "w").close()
    os.rename(tmp, root)
    log(f"root file system made in {time.monotonic() - start:.0f} s: {root}")
    return root


class Machine:
    """One container: an overlay over the cached root, booted with systemd on the test's bridge."""

    def __init__(self, name, address, root, work, pubkey):
        self.name, self.address = name, address
        self.dir = os.path.join(work, "machines", name)
        self.merged = os.path.join(self.dir, "root")
        for d in ("upper", "work", "root"):
            os.makedirs(os.path.join(self.dir, d), exist_ok=True)
        run(["mount", "-t", "overlay", "overlay", "-o",
             f"lowerdir={root},upperdir={self.dir}/upper,workdir={self.dir}/work", self.merged])
        self.mounted = True
        self.proc = None
        self.put("etc/hostname", name + "\n")
        self.put("etc/systemd/network/10-host0.network",
                 f"[Match]\nName=host0\n\n[Network]\nAddress={address}/24\nLinkLocalAddressing=no\n")
        self.put("root/.ssh/authorized_keys", pubkey, mode=0o600)
        os.chmod(os.path.join(self.merged, "root", ".ssh"), 0o700)
        run(["ssh-keygen", "-A", "-f", self.merged])
        # The host's clock is shared: chronyd measures and serves time, never sets it.
        self.put("etc/systemd/system/chrony.service.d/10-shared-clock.conf",
                 "# deploy test: containers share the host's clock\n[Unit]\nConditionCapability=\n\n"
                 "[Service]\nExecStart=\nExecStart=!/usr/sbin/chronyd -x\n")

    def put(self, path, text, mode=0o644):
        full = os.path.join(self.merged, path)
        os.makedirs(os.path.dirname(full), exist_ok=True)
        with open(full, "w") as f:
            f.write(text)
        os.chmod(full, mode)

    def boot(self):
        self.log = open(os.path.join(self.dir, "console.log"), "w")
        self.proc = subprocess.Popen(
            in_ns(["systemd-nspawn", "-D", self.merged, "--machine", f"{self.name}-{os.getpid()}",
                   "--hostname", self.name, "--register=no", "--keep-unit", "--boot", "--console=pipe",
                   "--network-bridge=br0", "--link-journal=no"]),
            stdin=subprocess.DEVNULL, stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)

    def running(self):
        """True while the container runs; its console log in the failure when it stopped."""
        if self.proc.poll() is not None:
            with open(os.path.join(self.dir, "console.log")) as f:
                raise AssertionError(f"{self.name}: systemd-nspawn exited with {self.proc.returncode}:\n{f.read()[-3000:]}")
        return True

    def stop(self):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)  # nspawn: an orderly shutdown of the container
            try:
                self.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=10)
        if self.mounted:
            run(["umount", "-l", self.merged], check=False)
            self.mounted = False


class DeployTest(unittest.TestCase):
    machines = []

    @classmethod
    def setUpClass(cls):
        for tool in ("systemd-nspawn", "debootstrap", "ssh", "ssh-keygen", "cpack", "ip"):
            if not shutil.which(tool):
                raise AssertionError(f"{tool} not found (deploy/install-deps.sh installs it)")
        if os.geteuid() != 0:
            raise AssertionError("the deploy test needs root (containers, mounts, a network namespace)")
        t0 = time.monotonic()
        # Runs even when setUpClass fails half-way (tearDownClass would not).
        cls.addClassCleanup(cls.remove_machines)
        # A run killed before its cleanup may have left its overlays mounted: never delete through them.
        with open("/proc/mounts") as f:
            stale = [line.split()[1] for line in f if line.split()[1].startswith(WORK + "/")]
        for mount in sorted(stale, reverse=True):
            run(["umount", "-l", mount])
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        cls.debs = build_packages(os.path.join(WORK, "packages"))
        root = rootfs(cls.debs)
        cls.frames = cls.render()
        # The operator's SSH identity and config; the machines' host keys are learnt on first use.
        ssh_dir = os.path.join(WORK, "ssh")
        os.makedirs(ssh_dir)
        run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-f", os.path.join(ssh_dir, "id")])
        cls.ssh_config = os.path.join(ssh_dir, "config")
        with open(cls.ssh_config, "w") as f:
            f.write(f"Host *\n  User root\n  IdentityFile {ssh_dir}/id\n  IdentitiesOnly yes\n"
                    f"  UserKnownHostsFile {ssh_dir}/known_hosts\n  StrictHostKeyChecking accept-new\n"
                    f"  LogLevel ERROR\n")
        with open(os.path.join(ssh_dir, "id.pub")) as f:
            pubkey = f.read()
        # The private network: a namespace with one bridge; the operator is .254 on it.
        run(["ip", "netns", "add", NS])
        run(["ip", "-n", NS, "link", "set", "lo", "up"])
        run(["ip", "-n", NS, "link", "add", "br0", "type", "bridge"])
        run(["ip", "-n", NS, "addr", "add", f"{OPERATOR}/24", "dev", "br0"])
        run(["ip", "-n", NS, "link", "set", "br0", "up"])
        cls.hub = Machine(HUB[0], HUB[1], root, WORK, pubkey)
        cls.machines.append(cls.hub)
        cls.nodes = {}
        for node_id, name, address in NODES:
            m = Machine(name, address, root, WORK, pubkey)
            cls.machines.append(m)
            cls.nodes[node_id] = m
            # The node's camera: the rendered recording, where its replay source reads it.
            shutil.copytree(os.path.join(cls.frames, f"cam{node_id}"),
                            os.path.join(m.merged, "var", "lib", "mocap-node", f"cam{node_id}"))
        for m in cls.machines:
            m.boot()
        for m in cls.machines:
            wait_for(f"{m.name} to answer over SSH", lambda m=m: m.running() and cls.ssh(
                m, "systemctl is-system-running --wait > /dev/null; true", check=False, timeout=60).returncode == 0, 90)
        log(f"{len(cls.machines)} machines up, {time.monotonic() - t0:.0f} s after the start")
        cls.inventory = os.path.join(WORK, "inventory")
        with open(cls.inventory, "w") as f:
            f.write(f"# deploy test installation\nhub {HUB[1]} address={HUB[1]} clients={SUBNET}.0/24 "
                    f"calibration={cls.frames}/calibration.json rate={RATE} deadline-ms=40\n")
            for node_id, _, address in NODES:
                f.write(f"node {node_id} {address} source=replay:/var/lib/mocap-node/cam{node_id} sync=sim:{RATE} "
                        f"replay_loop=yes threshold=32 log_level=warning\n")

    @classmethod
    def remove_machines(cls):
        for m in cls.machines:
            try:
                m.stop()
            except Exception as e:  # keep removing the others
                log(f"stopping {m.name}: {e}")
        run(["ip", "netns", "del", NS], check=False)
        cls.machines = []

    @classmethod
    def render(cls):
        out = os.path.join(WORK, "frames")
        hub = os.path.join(BIN, "mocap-hub")
        run([hub, "sim", "motion", "-o", f"{WORK}/motion.trc", "--frames", str(FRAMES), "--rate", str(RATE),
             "--markers", "20"])
        run([hub, "sim", "rig", "--motion", f"{WORK}/motion.trc", "--cameras", "3", "-o", f"{WORK}/rig.json"])
        run([hub, "sim", "render", "--motion", f"{WORK}/motion.trc", "--rig", f"{WORK}/rig.json", "-o", out,
             "--occlusion", "0", "--noise", "1.5"], timeout=300)
        return out

    @classmethod
    def ssh(cls, machine, command, check=True, timeout=60):
        return run(in_ns(["ssh", "-F", cls.ssh_config, "-o", "ConnectTimeout=5", "-o", "BatchMode=yes",
                          machine.address, command]), check=check, timeout=timeout)

    @classmethod
    def provision(cls, packages, *extra, timeout=600):
        start = time.monotonic()
        p = run(in_ns([os.path.join(SRC, "deploy", "provision"), cls.inventory, "--packages", packages,
                       "--ssh-config", cls.ssh_config, *extra]), check=False, timeout=timeout)
        log(f"provision {' '.join(extra)} -> exit {p.returncode} in {time.monotonic() - start:.1f} s")
        print(p.stdout + p.stderr, file=sys.stderr)
        return p

    def node_table(self):
        return json.loads(self.ssh(self.hub, "mocap-hub nodes --json").stdout)

    def main_pids(self):
        return {m.name: self.ssh(m, f"systemctl show -p MainPID --value mocap-{'hub' if m is self.hub else 'node'}").stdout.strip()
                for m in self.machines}

    def test_installation(self):
        packages = os.path.dirname(self.debs["mocap-node"])
        # ---- first run: a fresh installation ----
        p = self.provision(packages)
        self.assertEqual(p.returncode, 0, "provision of a fresh installation failed")
        self.assertIn("every node runs: 1 2 3", p.stdout)
        self.check_packages_and_units()
        self.check_keys()
        self.check_chrony()
        table = self.node_table()
        self.assertEqual(sorted(n["id"] for n in table if n["state"] == "running"), [1, 2, 3])
        addresses = {node_id: address for node_id, _, address in NODES}
        for n in table:
            self.assertEqual(n["firmware"], run(["dpkg-deb", "-f", self.debs["mocap-node"], "Version"])
                             .stdout.strip().split("-")[0])
            self.assertTrue(n["address"].startswith(addresses[n["id"]] + ":"), n["address"])
        self.check_capture()

        # ---- second run: nothing to do, nothing restarted ----
        pids = self.main_pids()
        p = self.provision(packages)
        self.assertEqual(p.returncode, 0)
        changes = [line for line in p.stdout.splitlines()
                   if re.search(r"\b(changed|installed|upgraded|downgraded|restarted|new:)", line)]
        self.assertEqual(changes, [], "a second provision run changed something")
        self.assertEqual(self.main_pids(), pids, "a second provision run restarted a service")

        # ---- an upgrade whose node cannot start is rolled back ----
        broken = self.broken_upgrade(packages)
        p = self.provision(broken, "--timeout", "15")
        self.assertEqual(p.returncode, 1, "an unhealthy upgrade must fail the run")
        good = run(["dpkg-deb", "-f", self.debs["mocap-node"], "Version"]).stdout.strip()
        for node_id, m in self.nodes.items():
            self.assertIn(f"node {node_id}: rolled back to mocap-node {good} and running", p.stdout)
            self.assertEqual(self.ssh(m, "dpkg-query -W -f='${Version}' mocap-node").stdout, good)
        p = self.provision(packages, "--check")
        self.assertEqual(p.returncode, 0, "after the rollback every node runs again")

    def check_packages_and_units(self):
        for m in self.machines:
            pkg = "mocap-hub" if m is self.hub else "mocap-node"
            version = run(["dpkg-deb", "-f", self.debs[pkg], "Version"]).stdout.strip()
            self.assertEqual(self.ssh(m, f"dpkg-query -W -f='${{Status}} ${{Version}}' {pkg}").stdout,
                             f"install ok installed {version}")
            self.assertEqual(self.ssh(m, f"systemctl is-enabled {pkg}").stdout.strip(), "enabled")
            self.assertEqual(self.ssh(m, f"systemctl is-active {pkg}").stdout.strip(), "active")
            show = self.ssh(m, f"systemctl show -p User -p Type -p NRestarts -p SubState {pkg}").stdout
            self.assertIn("User=mocap", show)
            self.assertIn("Type=notify", show)
            self.assertIn("NRestarts=0", show)
            # The user and directories come from the package (sysusers.d, tmpfiles.d); the
            # example config is a conffile.
            self.assertIn("uid=", self.ssh(m, "id mocap").stdout)
            state = "/var/lib/mocap-hub 750 mocap" if m is self.hub else "/var/lib/mocap-node 755 mocap"
            self.assertEqual(self.ssh(m, f"stat -c '%n %a %U' {state.split()[0]}").stdout.strip(), state)
            conffiles = self.ssh(m, f"dpkg-query -W -f='${{Conffiles}}' {pkg}").stdout
            self.assertIn(f"/etc/mocap/{pkg.split('-')[1]}.conf.example", conffiles)
        self.assertIn("gpio", self.ssh(self.nodes[1], "id -Gn mocap").stdout.split())

    def check_keys(self):
        keys = json.loads(self.ssh(self.hub, "mocap-hub keys list --dir /etc/mocap/keys --json").stdout)
        self.assertEqual(sorted(k["node"] for k in keys), [1, 2, 3])
        self.assertEqual(self.ssh(self.hub, "stat -c '%a %U' /etc/mocap/keys").stdout.strip(), "700 mocap")
        for node_id, m in self.nodes.items():
            hub_sum = self.ssh(self.hub, f"sha256sum < /etc/mocap/keys/node-{node_id}.key").stdout.split()[0]
            node_sum = self.ssh(m, "sha256sum < /etc/mocap/node.key").stdout.split()[0]
            self.assertEqual(hub_sum, node_sum, f"node {node_id} holds another key than the hub's")
            self.assertEqual(self.ssh(m, "stat -c '%a %U' /etc/mocap/node.key").stdout.strip(), "600 mocap")
            # One key per node: the others are different.
            other = self.ssh(self.hub, f"sha256sum < /etc/mocap/keys/node-{node_id % 3 + 1}.key").stdout.split()[0]
            self.assertNotEqual(hub_sum, other)
            self.assertIn("key_file = /etc/mocap/node.key", self.ssh(m, "cat /etc/mocap/node.conf").stdout)
        # Keys live on the machines only: no file of the repository (the fuzz corpora hold test
        # key files) and none left on the operator's side holds one of the installation's keys.
        sums = set(self.ssh(self.hub, "cat /etc/mocap/keys/*.key | sha256sum; "
                                      "for f in /etc/mocap/keys/*.key; do sha256sum < $f; done").stdout.split()) - {"-"}
        files = [os.path.join(SRC, f) for f in run(["git", "-C", SRC, "ls-files", "--cached", "--others",
                                                     "--exclude-standard"]).stdout.split()]
        for d, dirs, names in os.walk(WORK):
            dirs[:] = [x for x in dirs if x != "machines"]
            files += [os.path.join(d, n) for n in names]
        for path in files:
            if os.path.isfile(path) and os.path.getsize(path) < 1 << 20:
                with open(path, "rb") as f:
                    self.assertNotIn(hashlib.sha256(f.read()).hexdigest(), sums, f"{path} holds a node key")

    def check_chrony(self):
        hub_conf = self.ssh(self.hub, "chronyd -p -f /etc/chrony/chrony.conf").stdout
        self.assertIn(f"allow {SUBNET}.0/24", hub_conf)
        self.assertRegex(hub_conf, r"local stratum 8")
        for node_id, m in self.nodes.items():
            conf = self.ssh(m, "chronyd -p -f /etc/chrony/chrony.conf").stdout
            servers = [line for line in conf.splitlines() if line.startswith(("server", "pool", "peer"))]
            self.assertEqual(len(servers), 1, f"node {node_id} follows only the hub: {servers}")
            self.assertRegex(servers[0], rf"^server {re.escape(HUB[1])} .*minpoll 0 maxpoll 2")
            self.assertIn("makestep 0.1 3", conf)
            # chronyd on the node really takes the hub as its source ('*': selected).
            wait_for(f"node {node_id}'s chrony to select the hub", lambda m=m: re.search(
                rf"^\^\*\s+{re.escape(HUB[1])}\b", self.ssh(m, "chronyc -n sources", check=False).stdout, re.M), 60)
            tracking = self.ssh(m, "chronyc -n -c tracking").stdout.split(",")
            self.assertEqual(tracking[1], HUB[1])
            log(f"node {node_id}: chrony follows {tracking[1]}, offset {float(tracking[4]) * 1e6:.1f} us")

    def check_capture(self):
        self.ssh(self.hub, "mocap-hub capture start deploytest")
        time.sleep(5)
        self.ssh(self.hub, "mocap-hub capture stop")
        session = "/var/lib/mocap-hub/sessions/deploytest"
        info = json.loads(self.ssh(self.hub, f"cat {session}/session.json").stdout)
        log(f"capture: {info['frame_sets']} frame sets, {info['camera_frames']} camera frames, "
            f"{info['dropped_camera_frames']} dropped, {info['off_clock_frames']} off the session clock")
        self.assertEqual(info["capture_state"], "complete")
        self.assertEqual(sorted(info["cameras"]), [1, 2, 3])
        self.assertGreater(info["frame_sets"], 4 * RATE)
        self.assertGreater(info["camera_frames"], 0.95 * 3 * info["frame_sets"])
        self.assertEqual(info["off_clock_frames"], 0)
        self.ssh(self.hub, f"mocap-hub reconstruct {session} --calibration /etc/mocap/calibration.json "
                           f"-o /tmp/deploytest.trc --max-ray-distance-mm 3", timeout=300)
        result = self.ssh(self.hub, "cat /tmp/deploytest.trc").stdout.splitlines()
        self.assert_matches_truth(result, os.path.join(self.frames, "truth.trc"))

    def assert_matches_truth(self, result_lines, truth_path):
        """Each reconstructed frame against the truth frame its replay showed: the node replays the
        recording in a loop, so capture frame f shows truth frame (f + d) mod FRAMES for one d."""
        def rows(lines):
            out = {}
            for line in lines[5:]:
                cells = line.split("\t")
                if len(cells) < 5 or not cells[0].strip():
                    continue
                pts = [tuple(float(v) for v in cells[i:i + 3]) for i in range(2, len(cells) - 2, 3)
                       if cells[i].strip()]
                out[int(cells[0])] = pts
            return out
        with open(truth_path) as f:
            truth = rows(f.read().splitlines())
        result = rows(result_lines)
        self.assertGreater(len(result), 4 * RATE, "reconstructed frames")
        first_truth = min(truth)

        def errors(d):
            errs = []
            for f, pts in result.items():
                t = truth[first_truth + (f + d) % FRAMES]
                errs += [min(math.dist(p, q) for q in t) for p in pts]
            return errs
        best = min(range(FRAMES), key=lambda d: sorted(errors(d))[len(errors(d)) // 2])
        # As `mocap-hub eval` counts: a point within 20 mm of a true marker is matched, one
        # further away is a ghost.
        errs = sorted(errors(best))
        matched = [e for e in errs if e < 20.0]
        rmse = math.sqrt(sum(e * e for e in matched) / len(matched))
        truth_points = sum(len(truth[first_truth + (f + best) % FRAMES]) for f in result)
        log(f"reconstructed: {len(result)} frames, {len(matched)} of {truth_points} true points matched "
            f"({100 * len(matched) / truth_points:.1f} %), rmse {rmse:.3f} mm, median {errs[len(errs) // 2]:.3f} mm, "
            f"{(len(errs) - len(matched)) / len(result):.3f} ghosts per frame")
        self.assertLess(rmse, 2.0)
        self.assertLess(errs[len(errs) // 2], 0.5)
        self.assertGreater(len(matched), 0.9 * truth_points)
        self.assertLess(len(errs) - len(matched), 0.5 * len(result))

    def broken_upgrade(self, packages):
        """The same mocap-node with a higher version whose program exits at once (as a bad build
        would), beside the unchanged hub package."""
        out = os.path.join(WORK, "packages-broken")
        shutil.rmtree(out, ignore_errors=True)
        os.makedirs(out)
        tree = os.path.join(out, "tree")
        run(["dpkg-deb", "-R", self.debs["mocap-node"], tree])
        with open(os.path.join(tree, "usr", "bin", "mocap-node"), "w") as f:
            f.write("#!/bin/sh\necho 'mocap-node: error: deliberately broken build' >&2\nexit 3\n")
        control = os.path.join(tree, "DEBIAN", "control")
        with open(control) as f:
            text = f.read()
        version = re.search(r"^Version: (.*)$", text, re.M).group(1)
        with open(control, "w") as f:
            f.write(text.replace(f"Version: {version}", f"Version: {version}+broken1"))
        os.remove(os.path.join(tree, "DEBIAN", "md5sums"))
        arch = re.search(r"^Architecture: (.*)$", text, re.M).group(1)
        run(["dpkg-deb", "--root-owner-group", "-b", tree, os.path.join(out, f"mocap-node_{version}+broken1_{arch}.deb")])
        shutil.rmtree(tree)
        shutil.copy(self.debs["mocap-hub"], out)
        return out


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit("deploy: terminated (ctest timeout?)"))
    unittest.main(argv=sys.argv[:1] + sys.argv[4:], verbosity=2)
