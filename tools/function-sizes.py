#!/usr/bin/env python3
"""Lists C++ function definitions longer than N lines, longest first.

    python3 tools/function-sizes.py [-n N] [--exclude PATH]... [PATH...]

PATH is a file or a folder searched for *.cpp, *.hpp, *.cc, *.h, *.c
(default: protocol harness reports tools fuzz tests). N defaults to 120.
A function's size is its lines from the first line of its signature to its
closing brace; lambdas and local classes inside it count toward it. Test
bodies (TEST(...) { ... }) are functions too. Prints one line a function,
"LINES file:line name", and exits 0 whatever it finds: it reports, the
reader decides.

Brace matching on text without comments, string and character literals and
preprocessor lines, which is enough for this code base's style; it is not a
C++ parser (a macro that opens a brace it does not close would confuse it).
"""
import argparse
import os
import re
import sys

EXTENSIONS = (".cpp", ".hpp", ".cc", ".h", ".c")
DEFAULT_PATHS = ("protocol", "harness", "reports", "tools", "fuzz", "tests")


def blank(text):
    """The text with comments, literals and preprocessor lines replaced by
    blanks (newlines kept, so line numbers stay). String literals become ""."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            # A preprocessor line, with its continuations.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if c == "\n":
            line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        m = re.match(r'(?:u8|u|U|L)?R"([^ ()\\\t\n]{0,16})\(', text[i:i + 24])
        if m and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + m.group(1) + '"'
            end = text.find(close, i + m.end())
            end = n if end < 0 else end + len(close)
            out.append('""' + re.sub(r"[^\n]", " ", text[i + 2:end]))
            i = end
            continue
        if c == '"' or (c == "'" and not digit_separator(text, i)):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + " " * (j - i - 2) + c if j - i >= 2 else " " * (j - i))
            i = j
            continue
        out.append(c)
        i += 1
    return "".join(out)


def digit_separator(text, i):
    """Whether the quote at i is a digit separator (3'600'000)."""
    j = i
    while j > 0 and (text[j - 1].isalnum() or text[j - 1] in "_.'"):
        j -= 1
    return j < i and text[j].isdigit()


def top_level_closes(h, opening, closing):
    """The indices at which a top-level `opening` is closed, in order, and the
    depth left open at the end."""
    depth, closes = 0, []
    for k, ch in enumerate(h):
        if ch == opening:
            depth += 1
        elif ch == closing:
            depth -= 1
            if depth == 0:
                closes.append(k)
    return closes, depth


def paren_depth_zero_close(h):
    """The index of the last ')' that closes a top-level '(' (-1: none), and
    whether every '(' is closed."""
    closes, depth = top_level_closes(h, "(", ")")
    return (closes[-1] if closes else -1), depth == 0


def without_template_prefix(h):
    """The header without its leading template<...> clauses."""
    h = h.strip()
    while re.match(r"template\s*<", h):
        closes, _ = top_level_closes(h, "<", ">")
        if not closes:
            return h
        h = h[closes[0] + 1:].strip()
    return h


def is_function_header(h):
    """Whether a brace after this text (blanked, its own braced initializers
    included) opens a function body: a parameter list, then nothing,
    qualifiers, a trailing return type or a constructor's initializer list."""
    last_close, _ = paren_depth_zero_close(h)
    if last_close < 0:
        return False
    tail = h[last_close + 1:].strip()
    if tail == "" or tail.startswith("->"):
        return True
    if re.fullmatch(r"(?:(?:const|noexcept|override|final|mutable|volatile|&&|&|try)\s*)+", tail):
        return True
    if re.fullmatch(r"noexcept\s*\(.*\)\s*(?:override|final)?", tail, re.S):
        return True
    if re.search(r"\)\s*(?:noexcept\s*)?:[^:]", h):  # Foo::Foo(...) : member_(...), other_{...}
        return True
    return False


def brace_kind(header):
    """What a '{' after `header` opens: "init" (a braced initializer, part of
    the header of what follows), "function" or "scope" (namespace, class,
    enum, extern "C": look inside)."""
    _, balanced = paren_depth_zero_close(header)
    if not balanced:
        return "init"  # inside a parameter list or a decltype
    h = without_template_prefix(header)
    if h == "" or re.match(r"(inline\s+)?namespace\b", h) or re.fullmatch(r'extern\s*""', h):
        return "scope"
    if re.match(r"(typedef\s+)?(class|struct|union|enum)\b", h) and not is_function_header(h):
        return "scope"
    if is_function_header(h):
        return "function"
    if re.search(r"(=|\w|\]|>|,)\s*$", h):
        return "init"
    return "scope"


def function_name(header):
    h = " ".join(header.split())
    m = re.search(r"([A-Za-z_][\w:~<>]*|operator\s*\S+)\s*\(", h)
    if not m:
        return h[:60]
    name = m.group(1)
    if re.fullmatch(r"[A-Z][A-Z0-9_]*", name.split("::")[-1]):  # TEST(Suite, Name), RC_GTEST_PROP(...)
        close = h.find(")", m.end())
        return h[m.start():close + 1] if close > 0 else name
    return name


def functions(text):
    """(first line, last line, name) of every function definition."""
    code = blank(text)
    line_of = []
    line = 1
    for ch in code:
        line_of.append(line)
        if ch == "\n":
            line += 1
    found = []
    header_start = 0  # where the text before the next brace of this level starts
    i, n = 0, len(code)
    while i < n:
        ch = code[i]
        if ch in ";}":
            header_start = i + 1
        elif ch == "{":
            header = code[header_start:i]
            close = matching(code, i)
            kind = brace_kind(header)
            if kind == "function":
                first = header_start + (len(header) - len(header.lstrip()))
                found.append((line_of[first], line_of[min(close, n - 1)], function_name(header)))
                i = close + 1
                header_start = i
                continue
            if kind == "init":
                i = close + 1
                continue
            # namespace, class, struct, union, enum, extern "C": look inside.
            header_start = i + 1
        i += 1
    return found


def matching(code, i):
    depth = 0
    for k in range(i, len(code)):
        if code[k] == "{":
            depth += 1
        elif code[k] == "}":
            depth -= 1
            if depth == 0:
                return k
    return len(code) - 1


def sources(paths, excludes):
    excluded = [os.path.normpath(e) for e in excludes]

    def skip(p):
        p = os.path.normpath(p)
        return any(p == e or p.startswith(e + os.sep) for e in excluded)

    for p in paths:
        if os.path.isfile(p):
            if not skip(p):
                yield p
            continue
        for root, dirs, files in os.walk(p):
            dirs[:] = sorted(d for d in dirs if not skip(os.path.join(root, d)))
            for f in sorted(files):
                path = os.path.join(root, f)
                if f.endswith(EXTENSIONS) and not skip(path):
                    yield path


def main():
    ap = argparse.ArgumentParser(description="C++ functions longer than N lines, longest first.")
    ap.add_argument("-n", type=int, default=120, help="list functions longer than N lines (default 120)")
    ap.add_argument("--exclude", action="append", default=[], help="a file or folder to leave out (repeatable)")
    ap.add_argument("paths", nargs="*", default=list(DEFAULT_PATHS))
    args = ap.parse_args()
    rows = []
    for path in sources(args.paths, args.exclude):
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        for first, last, name in functions(text):
            size = last - first + 1
            if size > args.n:
                rows.append((size, path, first, name))
    rows.sort(key=lambda r: (-r[0], r[1], r[2]))
    for size, path, first, name in rows:
        print(f"{size:5d} {path}:{first} {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
