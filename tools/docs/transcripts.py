#!/usr/bin/python3
"""Runs the shell transcripts of the documentation as tests (cram-style).

  tools/docs/transcripts.py --sabus BUILD/tools/sabus --source SRC --work DIR [FILE.md...]

A transcript is a fenced block whose first line starts with "$ ". Each "$ "
line is a command; the lines after it, up to the next command, are what it
prints (standard output and standard error together). Without FILE.md
arguments: README.md and every docs/**/*.md of SRC.

Running a block (docs/ci.md, "The documentation is tested"):
  - the blocks of one file in one fresh directory, in order, so a file one
    block writes is there for the next; it holds a copy of the source tree's
    vectors/, links to its docs/, protocol/, reports/ and tests/, and the built
    binary as `build/tools/sabus` and as `sabus` on PATH;
  - each block in one bash, so `&`, `%1`, `$?` and files carry from one
    command to the next; NO_COLOR set, standard input empty;
  - "/tmp/" in a command is the block's own temporary directory, and each
    127.0.0.1:PORT a free port, so runs never collide; the output reads them
    back as written;
  - a `sabus` command runs on a pseudo-terminal (script(1)), as a reader
    would type it; what the terminal shows is compared (a progress line
    rewritten in place leaves its last text); other commands run in the
    block's shell;
  - a command ending in "&" runs in the background; the test waits (up to
    30 s: a loaded CI machine starts a simulator slowly) until it has printed
    as many lines as the block shows under it;
  - every job still running at the end of the block is stopped.

A block preceded by a comment `<!-- transcript: not-run (REASON) -->` is not
run (a USB port, a run of many minutes); its `sabus` commands are checked
like every other: the subcommand exists and each option appears in its
`--help` (or the program's).

Every relative link of a page must name a file that exists and, with an
anchor, a heading of it (so the README's two-click paths hold).

Expected and actual lines are compared after the same normalisation (RULES
below: times, durations, paths, temporary names, versions and the counts that
move with the suite; "0 failed" stays exact). An expected line "…" matches
any number of lines (indented or not); an expected line ending in "…"
matches a line that
starts with the rest. Exit 1 on any difference, with a diff per command.
"""

import argparse
import difflib
import glob
import os
import re
import shlex
import shutil
import socket
import subprocess
import sys
import time

# The normaliser: (pattern, replacement), applied in order to each line of
# both the expected and the actual output.
RULES = [
    # versions: the source revision moves with every commit
    (r"sabus \d+\.\d+\.\d+ \(git [^)]*\)", "sabus VERSION"),
    # ISO times, a sim or proxy transcript's leading seconds, wall times
    (r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?Z", "TIME"),
    (r"^\s*\d+\.\d{3} (?=\S)", "T "),
    (r"\b\d+(\.\d+)?\s?(ms|s|min)\b", "DUR"),
    (r"\b\d+:\d\d\b", "DUR"),
    (r"\bround trip DUR\b", "round trip DUR"),
    # paths: pseudo-terminals, temporary names, ephemeral client ports
    (r"/dev/pts/\d+", "/dev/pts/N"),
    (r"\btmp\.[A-Za-z0-9]{6,}", "tmp.X"),
    (r"(client 127\.0\.0\.1:)\d+", r"\1PORT"),
    # counts that move with the suite: vectors, files, entries, cells, fields
    (r"\b[1-9]\d* failed\b", "N failed"),
    (r"\b\d+ (passed|skipped|known failures?|need|above|vectors?|files|entries|cells|fields|vector\(s\)|must vector\(s\)|step\(s\)|frame\(s\)|writes|replies|liveness probes)\b", r"N \1"),
    (r"\b\d+ of \d+\b", "N of N"),
    (r"\(\d+\):$", "(N):"),
    (r"\b\d+ new failure\(s\)", "N new failure(s)"),
    (r"\b\d+ (ack|nak|offline|silence|garbage|refused)\b", r"N \1"),
    (r"(bytes_sent|bytes_received|wall_s)=[\d.]+", r"\1=N"),
    (r"\[ *\d+/\d+\]", "[N/N]"),
    # diff's hunk lines: the line numbers of a file that grows
    (r"^\d+(,\d+)?([acd])\d+(,\d+)?$", r"N\2N"),
]
COMPILED = [(re.compile(p), r) for p, r in RULES]
ELLIPSIS = "…"
NOT_RUN = re.compile(r"<!--\s*transcript:\s*not-run\b(.*?)-->")


def normalise(line):
    line = line.rstrip()
    for pattern, repl in COMPILED:
        line = pattern.sub(repl, line)
    return line


def match(expected, actual):
    """expected lines (with … wildcards) against actual lines, both normalised."""
    memo = {}

    def go(i, j):
        key = (i, j)
        if key in memo:
            return memo[key]
        if i == len(expected):
            ok = j == len(actual)
        elif expected[i].strip() == ELLIPSIS:
            ok = any(go(i + 1, k) for k in range(j, len(actual) + 1))
        elif j == len(actual):
            ok = False
        elif expected[i].endswith(ELLIPSIS):
            ok = actual[j].startswith(expected[i][:-1].rstrip()) and go(i + 1, j + 1)
        else:
            ok = expected[i] == actual[j] and go(i + 1, j + 1)
        memo[key] = ok
        return ok

    return go(0, 0)


class Block:
    def __init__(self, path, line, not_run):
        self.path, self.line, self.not_run = path, line, not_run
        self.steps = []  # [command, [expected lines]]


def blocks_of(path):
    lines = open(path, encoding="utf-8").read().split("\n")
    out, i, previous = [], 0, ""
    while i < len(lines):
        fence = re.match(r"^(\s*)(```|~~~)", lines[i])
        if not fence:
            if lines[i].strip():
                previous = lines[i]
            i += 1
            continue
        indent, marker = fence.group(1), fence.group(2)
        start, body = i + 1, []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(marker):
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        i += 1
        previous_line = previous
        previous = ""
        if not body or not body[0].startswith("$ "):
            continue
        block = Block(path, start + 1, NOT_RUN.search(previous_line))
        for b in body:
            if b.startswith("$ "):
                block.steps.append([b[2:], []])
            else:
                block.steps[-1][1].append(b)
        out.append(block)
    return out


class Help:
    """Options and subcommands of `sabus [SUB [SUBSUB]] --help`."""

    def __init__(self, sabus):
        self.sabus, self.cache = sabus, {}

    def text(self, chain):
        key = tuple(chain)
        if key not in self.cache:
            r = subprocess.run([self.sabus, *chain, "--help"], capture_output=True, text=True, timeout=20)
            self.cache[key] = r.stdout if r.returncode == 0 else None
        return self.cache[key]

    @staticmethod
    def subcommands(text):
        subs, inside = [], False
        for line in text.split("\n"):
            if re.match(r"^(SUBCOMMANDS|Subcommands):", line):
                inside = True
                continue
            if inside:
                m = re.match(r"^  (\S+)", line)
                if m:
                    subs.append(m.group(1))
                elif line and not line.startswith(" "):
                    inside = False
        return subs

    @staticmethod
    def has_option(text, option):
        return re.search(r"(^|[\s,])" + re.escape(option) + r"([\s,=]|$)", text, re.M) is not None


def check_options(block, help_):
    """Errors for the `sabus` commands of a block: unknown subcommands or options."""
    errors = []
    for command, _ in block.steps:
        try:
            lexer = shlex.shlex(command.rstrip("&").strip(), posix=True, punctuation_chars=True)
            lexer.whitespace_split = True
            tokens = list(lexer)
        except ValueError as e:
            errors.append(f"{command}: {e}")
            continue
        segments, current = [], []
        for t in tokens:
            if t in ("|", "||", "&&", ";", "&", ">", "<", ">>", "2>", "2>&1"):
                segments.append(current)
                current = []
            else:
                current.append(t)
        segments.append(current)
        for seg in segments:
            if not seg or os.path.basename(seg[0]) != "sabus":
                continue
            top = help_.text([])
            chain, texts, args = [], [top], seg[1:]
            k = 0
            while k < len(args):
                a = args[k]
                if a.startswith("-") and a != "-" and not re.match(r"^-\d", a):
                    option = a.split("=", 1)[0]
                    if not any(t and Help.has_option(t, option) for t in texts):
                        errors.append(f"{command}: sabus {' '.join(chain)}: no option {option}")
                elif not chain or Help.subcommands(texts[-1]):
                    subs = Help.subcommands(texts[-1])
                    if a in subs:
                        chain.append(a)
                        texts.append(help_.text(chain))
                    elif not chain and not (k > 0 and args[k - 1].startswith("-")):
                        # (a word after an option is taken as its value)
                        errors.append(f"{command}: no subcommand {a} (sabus --help lists {', '.join(subs)})")
                        break
                k += 1
    return errors


def anchors_of(path):
    """GitHub's anchors of a Markdown file's headings."""
    out, fenced = set(), False
    for line in open(path, encoding="utf-8"):
        if re.match(r"^\s*(```|~~~)", line):
            fenced = not fenced
        m = None if fenced else re.match(r"^#{1,6} (.*)$", line)
        if m:
            text = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower())
            out.add(text.replace(" ", "-"))
    return out


def check_links(path, source):
    """Errors for relative links of a page whose file or anchor does not exist."""
    errors, text = [], open(path, encoding="utf-8").read()
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    for m in re.finditer(r"\]\(([^)\s]+)\)", text):
        target = m.group(1)
        if re.match(r"^[a-z]+:", target):
            continue
        file, _, anchor = target.partition("#")
        full = os.path.normpath(os.path.join(os.path.dirname(path), file)) if file else path
        rel = os.path.relpath(path, source)
        if not os.path.exists(full):
            errors.append(f"{rel}: link to {target}: no such file")
        elif anchor and full.endswith(".md") and anchor not in anchors_of(full):
            errors.append(f"{rel}: link to {target}: no such heading")
    return errors


def on_terminal(command):
    """A `sabus` command in the foreground runs on a pseudo-terminal (script(1)),
    as a reader types it: what it prints is what they see."""
    words = command.split()
    return bool(words) and os.path.basename(words[0]) == "sabus"


def terminal_text(text):
    """What a terminal shows of a pty's output: CR LF as LF, a line rewritten
    after CR as its last text, control sequences (clear line) gone."""
    text = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", text.replace("\r\n", "\n"))
    return "\n".join(line.rsplit("\r", 1)[-1] for line in text.split("\n"))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def make_work_dir(work, args):
    """A fresh directory for the blocks of one file: a copy of vectors/ (a
    transcript may write there), links to docs/, protocol/, reports/ and
    tests/ (the coverage gate's known gaps), the
    binary as build/tools/sabus and as sabus on PATH, and tmp/."""
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.join(work, "build", "tools"))
    os.makedirs(os.path.join(work, "tmp"))
    os.makedirs(os.path.join(work, "bin"))
    shutil.copytree(os.path.join(args.source, "vectors"), os.path.join(work, "vectors"), symlinks=True)
    for d in ("docs", "protocol", "reports", "tests"):
        os.symlink(os.path.join(args.source, d), os.path.join(work, d))
    os.symlink(args.sabus, os.path.join(work, "build", "tools", "sabus"))
    os.symlink(args.sabus, os.path.join(work, "bin", "sabus"))


def run_block(block, index, args, work):
    tmp = os.path.join(work, "tmp") + "/"

    ports = {}

    def substitute(command):
        command = command.replace("/tmp/", tmp)
        def port(m):
            if m.group(1) not in ports:
                ports[m.group(1)] = str(free_port())
            return "127.0.0.1:" + ports[m.group(1)]
        return re.sub(r"127\.0\.0\.1:(\d{2,5})", port, command)

    script = ["set +e -m", f"cd {shlex.quote(work)}", "exec </dev/null", "rm -rf .t; mkdir .t",
              "__wait() { for _ in $(seq 300); do [ \"$(wc -l <\"$1\")\" -ge \"$2\" ] && return; sleep 0.1; done; }"]
    for n, (command, expected) in enumerate(block.steps):
        c = substitute(command)
        if c.rstrip().endswith("&") and not c.rstrip().endswith("&&"):
            c = c.rstrip()[:-1]
            script.append(f"{c} >.t/out.{n} 2>&1 &")
            script.append(f"__wait .t/out.{n} {len([e for e in expected if e.strip() != ELLIPSIS])}")
        elif on_terminal(c):
            script.append(f"script -qec {shlex.quote(c)} /dev/null >.t/out.{n} 2>&1; __rc=$?; echo $__rc >.t/rc.{n}; (exit $__rc)")
        else:
            script.append(f"{{ {c}\n}} >.t/out.{n} 2>&1; __rc=$?; echo $__rc >.t/rc.{n}; (exit $__rc)")
    script.append("for j in $(jobs -p); do kill -TERM $j 2>/dev/null; done; wait")
    with open(os.path.join(work, f"script{index}.sh"), "w") as f:
        f.write("\n".join(script) + "\n")
    env = dict(os.environ, NO_COLOR="1", SHELL="/bin/bash", PATH=os.path.join(work, "bin") + ":" + os.environ["PATH"],
               TMPDIR=os.path.join(work, "tmp"))
    env.pop("SABUS_DATA_DIR", None)
    started = time.monotonic()
    try:
        subprocess.run(["bash", os.path.join(work, f"script{index}.sh")], cwd=work, env=env, timeout=args.timeout,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        return [f"{block.path}:{block.line}: the block ran longer than {args.timeout} s"], time.monotonic() - started
    errors = []
    back = {v: k for k, v in ports.items()}
    for n, (command, expected) in enumerate(block.steps):
        try:
            actual = open(os.path.join(work, ".t", f"out.{n}"), encoding="utf-8", errors="replace", newline="").read()
        except FileNotFoundError:
            actual = ""
        actual = terminal_text(actual).replace(tmp, "/tmp/").replace(work + "/", "")
        actual = re.sub(r"127\.0\.0\.1:(\d+)", lambda m: "127.0.0.1:" + back.get(m.group(1), m.group(1)), actual)
        actual_lines = actual.split("\n")
        if actual_lines and actual_lines[-1] == "":
            actual_lines.pop()
        e = [normalise(x) if x.strip() != ELLIPSIS else ELLIPSIS for x in expected]
        a = [normalise(x) for x in actual_lines]
        if not match(e, a):
            diff = "\n".join(difflib.unified_diff(e, a, "shown", "printed", lineterm=""))
            errors.append(f"{block.path}:{block.line}: $ {command}\n{diff}")
    return errors, time.monotonic() - started


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    p.add_argument("--sabus", required=True)
    p.add_argument("--source", required=True)
    p.add_argument("--work", required=True)
    p.add_argument("--timeout", type=float, default=30)
    p.add_argument("files", nargs="*")
    args = p.parse_args()
    args.sabus, args.source, args.work = (os.path.realpath(x) for x in (args.sabus, args.source, args.work))
    files = args.files or [os.path.join(args.source, "README.md")] + sorted(
        glob.glob(os.path.join(args.source, "docs", "**", "*.md"), recursive=True))
    help_ = Help(args.sabus)
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    errors, ran, skipped, index, started = [], 0, 0, 0, time.monotonic()
    for number, path in enumerate(files):
        work = os.path.join(args.work, f"{number}-{os.path.basename(path)[:-3]}")
        made = False
        errors += check_links(path, args.source)
        for block in blocks_of(path):
            rel = os.path.relpath(block.path, args.source)
            block.path = rel
            errors += check_options(block, help_)
            if block.not_run:
                skipped += 1
                continue
            index += 1
            if not made:
                make_work_dir(work, args)
                made = True
            errs, seconds = run_block(block, index, args, work)
            ran += 1
            print(f"ran {rel}:{block.line} ({len(block.steps)} commands) in {seconds:.1f} s")
            errors += errs
    for e in errors:
        print(e, file=sys.stderr)
    print(f"transcripts: {ran} run, {skipped} not run (options checked), {len(errors)} error(s), "
          f"{time.monotonic() - started:.1f} s")
    return 1 if errors or ran == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
