#!/usr/bin/python3
"""sabus against real peers of RFC 2217 and TCP device servers (issue 23).

Run with Debian's /usr/bin/python3, which has pyserial (python3-serial).
Every peer is started here and killed on the way out; every wait has a
bound. Usage: rfc2217_peers.py SABUS WORKDIR CASE, CASE one of:
  ser2net         ser2net's telnet(rfc2217) accepter in front of `sabus sim
                  --pty`, and `sabus run --port rfc2217://...` through it:
                  the vectors of §1, §3.1, §3.2 and the empty-slot reads.
  pyserial        pyserial's rfc2217:// client against `sabus sim --rfc2217`:
                  a status poll, an empty-slot read (its 7Fh bytes are 0xFF
                  with parity), a baud-rate change the sim logs.
  sabus-client    `sabus run --port rfc2217://...` against `sabus sim
                  --rfc2217`, 8N1 with sabus's parity and --line 7E1 (the
                  sim then does the UART's parity work).
  second-client   a second client of `sabus sim --tcp` and of `--rfc2217`
                  refused at once with a text line; with --takeover it is
                  served and the first one is disconnected.
"""
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time

SABUS, WORK, CASE = sys.argv[1], sys.argv[2], sys.argv[3]
children = []


def fail(message):
    print("FAIL: " + message, flush=True)
    sys.exit(1)


def start(args, out_path):
    out = open(out_path, "w")
    p = subprocess.Popen(args, stdout=out, stderr=subprocess.STDOUT)
    children.append(p)
    return p


def stop_all():
    for p in children:
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def wait_for(predicate, what, seconds=10):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    fail("timed out waiting for " + what)


def read_text(path):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except FileNotFoundError:
        return ""


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def start_sim(args, name):
    out = os.path.join(WORK, name + ".out")
    start([SABUS, "sim"] + args + ["--log", os.path.join(WORK, name + ".log")], out)
    ready = wait_for(lambda: re.search(r"READY (\S+)(?: (\S+))?", read_text(out)), "sabus sim READY (" + name + ")")
    return ready


# SAbus framing as §1 has it: STX, address, command, data, ETX, a check byte
# (XOR of all before it, READING-NOTES 7), even parity in bit 7 of each byte.
def with_parity(b):
    return b | (0x80 if bin(b).count("1") % 2 else 0)


def frame(command, data=b"", address=0x32):
    body = bytes([0x02, address, command]) + data + bytes([0x03])
    check = 0
    for b in body:
        check ^= b
    return bytes(with_parity(b) for b in body + bytes([check & 0x7F]))


def read_exactly(port, n, what):
    got = port.read(n)
    if len(got) != n:
        fail("%s: %d bytes of %d came back: %s" % (what, len(got), n, got.hex(" ")))
    return got


def case_ser2net():
    if shutil.which("ser2net") is None:
        fail("ser2net is not installed (tools/install-deps.sh installs it)")
    link = os.path.join(WORK, "pty")
    start_sim(["--pty", "--link", link], "sim")
    port = free_port()
    config = os.path.join(WORK, "ser2net.yaml")
    with open(config, "w") as f:
        # ser2net 4 YAML: a telnet accepter with RFC 2217 on loopback in
        # front of the pty's real name (the link may go away before it).
        f.write("connection: &sabus\n")
        f.write("  accepter: telnet(rfc2217),tcp,127.0.0.1,%d\n" % port)
        f.write("  connector: serialdev,%s,9600n81,local\n" % os.path.realpath(link))
    s2n = start(["ser2net", "-n", "-d", "-c", config], os.path.join(WORK, "ser2net.out"))

    def listening():
        if s2n.poll() is not None:
            fail("ser2net exited: " + read_text(os.path.join(WORK, "ser2net.out")))
        try:
            socket.create_connection(("127.0.0.1", port), 0.2).close()
            return True
        except OSError:
            return False

    wait_for(listening, "ser2net to listen on port %d" % port)
    time.sleep(0.3)  # the probe connection above is closed on ser2net's side
    run_out = os.path.join(WORK, "run.out")
    args = [SABUS, "run", "--port", "rfc2217://127.0.0.1:%d" % port, "--pace", "0", "--verbose",
            "--json", os.path.join(WORK, "run.json")]
    for glob in ["framing-*", "ignore-*", "multidrop-*", "nak-*", "offline-*", "parity-*", "3.1-*", "3.2-*",
                 "3.11-read-satellite-empty-slot", "3.13-read-tle-empty-slot", "3.15-read-iess-empty-slot"]:
        args += ["--filter", glob]
    with open(run_out, "w") as out:
        try:
            status = subprocess.run(args, stdout=out, stderr=subprocess.STDOUT, timeout=600).returncode
        except subprocess.TimeoutExpired:
            fail("sabus run through ser2net did not finish in 600 s")
    text = read_text(run_out)
    print(text[-3000:])
    if status != 0 or not re.search(r"^\d+ passed, 0 failed", text, re.M):
        fail("sabus run through ser2net: exit %d" % status)
    # The 7Fh no-data marker of an empty slot is 0xFF on the wire with its
    # parity bit, doubled by ser2net: these pass only if it was unescaped.
    # (3.15's IESS read runs only on a profile that implements IESS.)
    for vector in ["3.11-read-satellite-empty-slot", "3.13-read-tle-empty-slot", "3.1-device-type-bytes"]:
        if not re.search(r"^PASS %s " % re.escape(vector), text, re.M):
            fail(vector + " did not pass through ser2net")
    if "negotiated BINARY, SUPPRESS-GO-AHEAD, COM-PORT-OPTION; 9600 baud 8N1" not in text:
        fail("the negotiation was not logged")
    print("sabus run through ser2net's RFC 2217 port: passed")


def open_pyserial(port, **kwargs):
    import serial  # Debian's python3-serial
    return serial.serial_for_url("rfc2217://127.0.0.1:%d" % port, baudrate=9600, timeout=2, **kwargs)


def case_pyserial():
    ready = start_sim(["--rfc2217", "127.0.0.1:0", "--emulate-line"], "sim")
    port = int(ready.group(2).rsplit(":", 1)[1])
    p = open_pyserial(port)
    try:
        p.write(frame(0x31))  # §3.2 status poll
        reply = read_exactly(p, 52, "status poll")
        if reply[0] != 0x06 or reply[2] != with_parity(0x31):
            fail("status poll reply: " + reply.hex(" "))
        # §3.11 read satellite of an empty slot: 7Fh 7Fh at bytes 3-4, each
        # 0xFF with its parity bit (escaped on the wire by the sim).
        empty = None
        for index in range(19, 0, -1):
            p.write(frame(0x3A, b"%02d" % index))
            reply = read_exactly(p, 32, "read satellite %d" % index)
            if reply[0] != 0x06:
                fail("read satellite %d: %s" % (index, reply.hex(" ")))
            if reply[3:5] == b"\xff\xff":
                empty = index
                break
        if empty is None:
            fail("no empty slot read back 0xFF 0xFF")
        p.baudrate = 4800  # SET-BAUDRATE: the sim emulates 4800 from now on
        p.write(frame(0x30))  # §3.1 device type
        reply = read_exactly(p, 11, "device type at 4800 baud")
        if reply[0] != 0x06:
            fail("device type reply: " + reply.hex(" "))
    finally:
        p.close()
    # A client whose port is 7E1 (bytesize 7, even parity): 7-bit characters
    # both ways, the parity made and checked by the sim for it.
    p = open_pyserial(port, bytesize=7, parity="E")
    try:
        p.write(bytes(b & 0x7F for b in frame(0x3A, b"%02d" % empty)))
        reply = read_exactly(p, 32, "read satellite %d at 7E1" % empty)
        if reply[0] != 0x06 or reply[3:5] != b"\x7f\x7f" or any(b & 0x80 for b in reply):
            fail("7E1 read of empty slot %d: %s" % (empty, reply.hex(" ")))
    finally:
        p.close()
    log = wait_for(lambda: "client gone" in read_text(os.path.join(WORK, "sim.log")) and
                   read_text(os.path.join(WORK, "sim.log")), "the sim to log the client leaving")
    if "client set 4800 baud: the line is emulated at that rate" not in log:
        fail("the sim did not log the baud rate change:\n" + log)
    print("pyserial's rfc2217:// client against sabus sim --rfc2217: status poll, empty slot %d, 4800 baud" % empty)


def case_sabus_client():
    ready = start_sim(["--rfc2217", "127.0.0.1:0", "--emulate-line"], "sim")
    port = int(ready.group(2).rsplit(":", 1)[1])
    for line in ["8N1", "7E1"]:
        out = os.path.join(WORK, "run-%s.out" % line)
        args = [SABUS, "run", "--port", "rfc2217://127.0.0.1:%d" % port, "--line", line, "--pace", "0",
                "--filter", "3.1-*", "--filter", "3.2-*", "--filter", "3.11-read-satellite-empty-slot"]
        with open(out, "w") as f:
            try:
                status = subprocess.run(args, stdout=f, stderr=subprocess.STDOUT, timeout=300).returncode
            except subprocess.TimeoutExpired:
                fail("sabus run --line %s did not finish in 300 s" % line)
        text = read_text(out)
        if status != 0 or not re.search(r"^\d+ passed, 0 failed", text, re.M) or \
                not re.search(r"^PASS 3.11-read-satellite-empty-slot ", text, re.M):
            fail("sabus run --line %s against sabus sim --rfc2217: exit %d\n%s" % (line, status, text))
        print("sabus run --line %s: %s" % (line, text.strip().splitlines()[-1]))
    log = read_text(os.path.join(WORK, "sim.log"))
    if "ignored" in log:
        fail("the sim ignored bytes:\n" + log)


def refused_text(port):
    s = socket.create_connection(("127.0.0.1", port), 5)
    s.settimeout(5)
    data = b""
    while True:
        chunk = s.recv(256)  # the server closes after its line: recv returns b""
        if not chunk:
            break
        data += chunk
    s.close()
    return data


def case_second_client():
    import serial
    # Raw TCP: the first client is served, the second refused at once.
    ready = start_sim(["--tcp", "127.0.0.1:0"], "tcp")
    port = int(ready.group(2).rsplit(":", 1)[1])
    first = socket.create_connection(("127.0.0.1", port), 5)
    first.settimeout(5)
    first.sendall(frame(0x30))
    if not first.recv(64).startswith(b"\x06"):
        fail("raw TCP: the first client got no reply")
    wait_for(lambda: "client connected" in read_text(os.path.join(WORK, "tcp.log")), "the first client's log line")
    text = refused_text(port)
    if not text.startswith(b"Port already in use"):
        fail("raw TCP: the second client read %r" % text)
    first.sendall(frame(0x30))
    if not first.recv(64).startswith(b"\x06"):
        fail("raw TCP: the first client lost its service after the refusal")
    first.close()
    if not re.search(r"client refused: .*: the port is in use by", read_text(os.path.join(WORK, "tcp.log"))):
        fail("raw TCP: the refusal was not logged")
    # RFC 2217: pyserial's second client is refused too (the text, then EOF).
    ready = start_sim(["--rfc2217", "127.0.0.1:0"], "rfc")
    port = int(ready.group(2).rsplit(":", 1)[1])
    p = open_pyserial(port)
    try:
        text = refused_text(port)
        if not text.startswith(b"Port already in use"):
            fail("RFC 2217: the second client read %r" % text)
        # Refused, pyserial's open fails: on the text and the close, or with
        # a reset when the close meets its negotiation unread.
        try:
            open_pyserial(port).close()
            fail("RFC 2217: pyserial's second client was served")
        except (serial.SerialException, OSError) as e:
            print("pyserial's second client: %s" % e)
        p.write(frame(0x30))
        if not read_exactly(p, 11, "the first client after the refusals").startswith(b"\x06"):
            fail("RFC 2217: the first client lost its service")
    finally:
        p.close()
    # --takeover: the newcomer is served, the first client disconnected.
    ready = start_sim(["--rfc2217", "127.0.0.1:0", "--takeover"], "takeover")
    port = int(ready.group(2).rsplit(":", 1)[1])
    p = open_pyserial(port)
    q = open_pyserial(port)
    try:
        q.write(frame(0x30))
        if not read_exactly(q, 11, "the client that took over").startswith(b"\x06"):
            fail("--takeover: the new client got no reply")
        try:
            p.write(frame(0x30))
            got = p.read(11)
            if got:
                fail("--takeover: the first client still got %r" % got)
        except (serial.SerialException, OSError):
            pass  # its connection was closed
    finally:
        q.close()
        p.close()
    if not re.search(r"takes over from .* \(--takeover\)", read_text(os.path.join(WORK, "takeover.log"))):
        fail("--takeover was not logged")
    print("second clients: refused on raw TCP and RFC 2217, served with --takeover")


try:
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    {"ser2net": case_ser2net, "pyserial": case_pyserial, "sabus-client": case_sabus_client,
     "second-client": case_second_client}[CASE]()
finally:
    stop_all()
