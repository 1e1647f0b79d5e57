"""Runs mutated VEX snippets through the geode binary and sorts the outcomes.

Takes the real snippets the repository holds (wrangles in examples/*.json,
snippets in docs/wrangle.md, the programs of crates/vex/tests), makes N
mutations of them (token deletion, duplication, swap and splice, random
characters, deep nesting, long operator chains up to 200 KB, huge loop
counts and array sizes, nested ifs 10,000 deep...), writes each into a
small network (a grid into a wrangle) and runs `geode cook` on it with a
timeout. Each run is one of:

  ok      exit 0
  error   exit 1 with a message (a clean refusal)
  crash   a signal, exit 101 or 134, 'panicked' or 'overflowed its stack'
          (or any other exit status)
  long    still running at the timeout, and stopped within 5 s of
          Ctrl-C (SIGINT) with geode's cancelled status: a runaway loop
          the user can stop, as in Houdini
  hang    still running at the timeout and not stopped by Ctrl-C

Deterministic for a --seed (the cases, not the timings). Prints the counts
(overall and per mutation) and saves every crash and hang under --out:
NNNN-KIND.vex (the snippet), NNNN-KIND.json (the network) and
NNNN-KIND.txt (mutation, exit status, the end of stderr).

  python3 tools/vex_mutate.py --geode target/debug/geode -n 300 --out /tmp/vm
  python3 tools/vex_mutate.py --write-seeds fuzz/seeds/vex_text

Standard library only.
"""

import argparse
import concurrent.futures
import glob
import hashlib
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The largest snippet a mutation builds (an operator chain up to 200 KB).
MAX_BYTES = 200 * 1024


# ---------------------------------------------------------------- the corpus


def wrangle_snippets(network):
    """Every wrangle snippet in a network document, subnets included."""
    out = []
    for node in (network.get("nodes") or {}).values():
        if not isinstance(node, dict):
            continue
        snippet = (node.get("params") or {}).get("snippet")
        if node.get("type") == "wrangle" and isinstance(snippet, str):
            out.append(snippet)
        if isinstance(node.get("network"), dict):
            out.extend(wrangle_snippets(node["network"]))
    return out


RUST_STRING = re.compile(r'r(#*)"(.*?)"\1|"((?:[^"\\]|\\.)*)"', re.S)
RUST_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "0": "\0", "\\": "\\", '"': '"', "'": "'"}


def rust_unescape(s):
    def one(m):
        e = m.group(1)
        if e.startswith("u{"):
            return chr(int(e[2:-1], 16))
        if e.startswith("x"):
            return chr(int(e[1:], 16))
        if e.startswith("\n"):
            return ""  # a line continuation
        return RUST_ESCAPES.get(e, e)

    return re.sub(r"\\(u\{[0-9a-fA-F]+\}|x[0-9a-fA-F]{2}|\n\s*|.)", one, s)


def looks_like_vex(s):
    """A statement or more: a snippet, not a message or an attribute name."""
    return ";" in s and len(s) >= 4 and not s.startswith(("line ", "error"))


def corpus(root):
    """(source, snippet) pairs, in a fixed order, each snippet once."""
    found = []
    for path in sorted(glob.glob(os.path.join(root, "examples", "*.json"))):
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
        for s in wrangle_snippets(doc.get("network", doc)):
            found.append(("examples/" + os.path.basename(path), s))
    wrangle_md = os.path.join(root, "docs", "wrangle.md")
    if os.path.exists(wrangle_md):
        with open(wrangle_md, encoding="utf-8") as f:
            text = f.read()
        # Snippets in the JSON of code blocks, and code spans that are statements.
        for m in re.finditer(r'"snippet"\s*:\s*("(?:[^"\\]|\\.)*")', text):
            found.append(("docs/wrangle.md", json.loads(m.group(1))))
        for m in re.finditer(r"`([^`\n]+)`", text):
            if looks_like_vex(m.group(1)):
                found.append(("docs/wrangle.md", m.group(1)))
    for path in sorted(glob.glob(os.path.join(root, "crates", "vex", "tests", "*.rs"))):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for m in RUST_STRING.finditer(text):
            s = m.group(2) if m.group(2) is not None else rust_unescape(m.group(3))
            if looks_like_vex(s):
                found.append(("crates/vex/tests/" + os.path.basename(path), s))
    seen, out = set(), []
    for src, s in found:
        if s.strip() and s not in seen:
            seen.add(s)
            out.append((src, s))
    return out


# ------------------------------------------------------------- the mutations

TOKEN = re.compile(
    r'"(?:[^"\\]|\\.)*"|[A-Za-z_][A-Za-z0-9_]*|\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+'
    r"|<<=|>>=|\+\+|--|&&|\|\||[-+*/%&|^<>=!]=|<<|>>|\[\]|\s+|."
)

OPERATORS = ["+", "-", "*", "/", "%", "&&", "||", "==", "!=", "<", ">=", "&", "|", "^", "<<", ">>"]

# Statements whose every form a cook must refuse or finish cleanly.
HEAVY = [
    "int a[]; resize(a, {n}); i@r = len(a);",
    "float a[]; resize(a, {n}); f@r = a[-1];",
    "vector a[]; resize(a, {n}); v@r = a[0];",
    "string s = \"x\"; for (int i = 0; i < {k}; i++) s += s; s@r = s;",
    "int a[] = array(1); for (int i = 0; i < {k}; i++) append(a, a); i@r = len(a);",
    "for (int i = 0; i < {n}; i++) {{ f@r += 1; }}",
    "int i = 0; while (i < {n}) {{ i++; }} i@r = i;",
    "for (int i = 0; i < {n}; i++) {{ for (int j = 0; j < {n}; j++) {{ f@r += j; }} }}",
    "f[]@r = array(); resize(f[]@r, {n});",
    "for (int i = 0; i < {k}; i++) addpoint(0, set(i, 0, 0));",
    "s@r = sprintf(\"%0{n}d\", 1);",
    "i[]@r = array(); for (int i = 0; i < {k}; i++) append(i[]@r, i);",
    "int a[]; a[{n}] = 1; i@r = len(a);",
]

HUGE = ["1000000", "100000000", "2147483647", "-1", "-2147483648", "4294967296", "1e30"]


def tokens(s):
    return TOKEN.findall(s)


def nest(rng):
    """Deep nesting of one kind."""
    depth = rng.choice([64, 256, 1000, 5000, 10000, 50000])
    kind = rng.randrange(7)
    if kind == 0:
        return "f@r = " + "(" * depth + "1" + ")" * depth + ";"
    if kind == 1:
        return "if (1) { " * depth + "f@r = 1;" + " }" * depth
    if kind == 2:
        return "{" * depth + "f@r = 1;" + "}" * depth
    if kind == 3:
        return "f@r = " + "sin(" * depth + "1" + ")" * depth + ";"
    if kind == 4:
        return "f@r = " + "1 ? " * depth + "1" + " : 0" * depth + ";"
    if kind == 5:
        return "f@r = " + rng.choice(["-", "!", "~", "+"]) * depth + "1;"
    return "int a[] = " + "{" * depth + "1" + "}" * depth + ";"


def chain(rng):
    """A long operator chain, up to 200 KB."""
    size = rng.choice([1 << 10, 1 << 14, 1 << 16, MAX_BYTES - 64])
    op = rng.choice(OPERATORS + ["mixed"])
    parts, n = ["f@r = 1"], 7
    while n < size:
        o = rng.choice(OPERATORS) if op == "mixed" else op
        t = o + rng.choice(["1", "@P.x", "2.5", "i@n"])
        parts.append(t)
        n += len(t)
    return "".join(parts) + ";"


def heavy(rng):
    n = rng.choice(HUGE)
    k = rng.choice(["40", "64", "100", "1000"])
    return rng.choice(HEAVY).format(n=n, k=k)


def random_chars(rng, s):
    """Random characters (controls, NUL, quotes, braces, far code points) spliced in."""
    pool = "\0\1\t\n\r\x7f\"'\\{}()[];@$`#" + "é€𝔵\u200b\ufeff\ud7ff"
    chars = []
    for _ in range(rng.choice([1, 4, 16, 256])):
        r = rng.random()
        if r < 0.5:
            chars.append(rng.choice(pool))
        elif r < 0.8:
            chars.append(chr(rng.randrange(32, 127)))
        else:
            chars.append(chr(rng.randrange(0x80, 0x2FFFF)))
    at = rng.randrange(len(s) + 1)
    text = s[:at] + "".join(chars) + s[at:]
    # JSON carries text: a lone surrogate cannot travel.
    return "".join(c for c in text if not 0xD800 <= ord(c) <= 0xDFFF)


def token_edit(rng, s, pool):
    t = tokens(s) or [";"]
    kind = rng.choice(["delete", "duplicate", "swap", "insert", "splice", "repeat"])
    i = rng.randrange(len(t))
    if kind == "delete":
        n = rng.choice([1, 1, 2, 5])
        del t[i : i + n]
    elif kind == "duplicate":
        t.insert(i, t[i])
    elif kind == "swap":
        j = rng.randrange(len(t))
        t[i], t[j] = t[j], t[i]
    elif kind == "insert":
        t.insert(i, rng.choice(pool))
    elif kind == "splice":
        other = tokens(rng.choice(pool_snippets))
        a = rng.randrange(len(other) + 1)
        b = min(len(other), a + rng.randrange(1, 12))
        t[i:i] = other[a:b]
    else:
        # One token many times over: `[[[[`, `;;;;`, `@@@@`.
        t.insert(i, t[i] * rng.choice([10, 1000, 20000]))
    return "".join(t), kind


pool_snippets = []


def mutate(rng, snippets, pool):
    """One case: (mutation name, snippet)."""
    r = rng.random()
    if r < 0.08:
        return "nesting", nest(rng)
    if r < 0.14:
        return "chain", chain(rng)
    if r < 0.22:
        return "heavy", heavy(rng)
    base = rng.choice(snippets)
    if r < 0.30:
        # A real snippet inside something heavy or deep.
        wrap = rng.choice(["for (int q = 0; q < 100000000; q++) {{ {s} }}", "while (1) {{ {s} }}", "{{{s}}}"])
        return "wrap", wrap.format(s=base)
    if r < 0.40:
        return "chars", random_chars(rng, base)
    s, names = base, []
    for _ in range(rng.choice([1, 1, 2, 3, 5])):
        s, kind = token_edit(rng, s, pool)
        names.append(kind)
    return "tokens:" + "+".join(sorted(set(names))), s


def cases(n, seed, found):
    rng = random.Random(seed)
    snippets = [s for _, s in found]
    pool_snippets[:] = snippets
    pool = sorted({t for s in snippets for t in tokens(s) if not t.isspace()})
    out = []
    for _ in range(n):
        kind, s = mutate(rng, snippets, pool)
        s = s.encode("utf-8")[:MAX_BYTES].decode("utf-8", "ignore")
        run_over = rng.choice(["points", "points", "primitives", "vertices", "detail"])
        out.append((kind, s, run_over))
    return out


# ---------------------------------------------------------------- the runs


def network(snippet, run_over):
    return {
        "geode": "network",
        "version": 1,
        "output": "w",
        "nodes": {
            "grid": {"type": "grid"},
            "w": {
                "type": "wrangle",
                "inputs": ["grid"],
                "params": {"snippet": snippet, "run_over": run_over},
            },
        },
    }


CRASH_TEXT = ("panicked", "overflowed its stack", "SIGSEGV", "SIGABRT", "memory allocation of")


def classify(code, stderr):
    if code is None:
        return "hang"
    if code == "long":
        return "long"
    if code == 0:
        return "ok"
    if code < 0 or code in (101, 134) or any(t in stderr for t in CRASH_TEXT):
        return "crash"
    if code == 1 and stderr.strip():
        return "error"
    return "crash"


def run_one(geode, work, index, snippet, run_over, timeout, env):
    path = os.path.join(work, "case-%05d.json" % index)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(network(snippet, run_over), f)
    p = subprocess.Popen(
        [geode, "cook", path],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env=env,
        start_new_session=True,
    )
    t0 = time.monotonic()
    try:
        _, err = p.communicate(timeout=timeout)
        code = p.returncode
    except subprocess.TimeoutExpired:
        # A long program is fine if the user can stop it: Ctrl-C, then
        # a grace period before it counts as a hang.
        os.killpg(p.pid, signal.SIGINT)
        try:
            _, err = p.communicate(timeout=5)
            code = "long" if p.returncode in (130, 1) else p.returncode
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            _, err = p.communicate()
            code = None
    os.remove(path)
    err = err.decode("utf-8", "replace")
    return classify(code, err), code, err, time.monotonic() - t0


def default_geode():
    target = os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target")
    return os.path.join(target, "debug", "geode")


def write_seeds(found, folder):
    """The corpus as fuzz seeds, one file per snippet, named by content."""
    os.makedirs(folder, exist_ok=True)
    for src, s in found:
        stem = re.sub(r"[^a-z0-9]+", "_", os.path.splitext(os.path.basename(src))[0].lower())
        digest = hashlib.sha1(s.encode("utf-8")).hexdigest()[:10]
        with open(os.path.join(folder, "%s_%s.vfl" % (stem, digest)), "w", encoding="utf-8") as f:
            f.write(s)
    print("wrote %d seeds to %s" % (len(found), folder))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--geode", default=default_geode(), help="the binary (default $CARGO_TARGET_DIR/debug/geode)")
    ap.add_argument("-n", type=int, default=3000, help="mutations to run (3000)")
    ap.add_argument("--seed", type=int, default=1, help="the cases' seed (1)")
    ap.add_argument("--out", default="vex_mutate_out", help="folder for crashes and hangs")
    ap.add_argument("--timeout", type=float, default=10.0, help="seconds per cook (10)")
    ap.add_argument("--jobs", type=int, default=2, help="cooks at once (2)")
    ap.add_argument("--memory-mb", default="2048", help="GEODE_MEMORY_MB for each cook (2048)")
    ap.add_argument("--write-seeds", metavar="DIR", help="write the corpus as fuzz seeds and exit")
    args = ap.parse_args()

    found = corpus(ROOT)
    if args.write_seeds:
        write_seeds(found, args.write_seeds)
        return 0
    if not os.access(args.geode, os.X_OK):
        print("no geode binary at %s (cargo build -p geode-cli, or --geode)" % args.geode, file=sys.stderr)
        return 2
    by_source = {}
    for src, _ in found:
        by_source[src] = by_source.get(src, 0) + 1
    print("corpus: %d snippets (%s)" % (len(found), ", ".join("%s %d" % kv for kv in sorted(by_source.items()))))
    todo = cases(args.n, args.seed, found)
    env = dict(os.environ, RAYON_NUM_THREADS="1", GEODE_MEMORY_MB=args.memory_mb, RUST_BACKTRACE="0")
    env.pop("GEODE_CACHE_DIR", None)
    os.makedirs(args.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="vex_mutate_")
    counts, per_kind, results = {}, {}, [None] * len(todo)
    t0 = time.monotonic()
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = {
                pool.submit(run_one, args.geode, work, i, s, ro, args.timeout, env): i
                for i, (_, s, ro) in enumerate(todo)
            }
            done = 0
            for fut in concurrent.futures.as_completed(futures):
                i = futures[fut]
                results[i] = fut.result()
                done += 1
                if done % 50 == 0:
                    print("  %d/%d (%.0f s)" % (done, len(todo), time.monotonic() - t0), flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for i, ((kind, snippet, run_over), (outcome, code, err, secs)) in enumerate(zip(todo, results)):
        counts[outcome] = counts.get(outcome, 0) + 1
        k = per_kind.setdefault(kind.split(":")[0], {})
        k[outcome] = k.get(outcome, 0) + 1
        if outcome in ("crash", "hang"):
            stem = os.path.join(args.out, "%04d-%s" % (i, outcome))
            with open(stem + ".vex", "w", encoding="utf-8") as f:
                f.write(snippet)
            with open(stem + ".json", "w", encoding="utf-8") as f:
                json.dump(network(snippet, run_over), f)
            with open(stem + ".txt", "w", encoding="utf-8") as f:
                f.write("mutation: %s\nrun_over: %s\nexit: %s\nseconds: %.1f\nbytes: %d\n\n%s\n"
                        % (kind, run_over, "timeout" if code is None else code, secs, len(snippet.encode()), err[-4000:]))
    total = sum(counts.values())
    print("ran %d cases in %.0f s (seed %d, timeout %g s, %d jobs, %s)"
          % (total, time.monotonic() - t0, args.seed, args.timeout, args.jobs, args.geode))
    for outcome in ("ok", "error", "long", "crash", "hang"):
        print("  %-6s %d" % (outcome, counts.get(outcome, 0)))
    print("by mutation:")
    for kind in sorted(per_kind):
        c = per_kind[kind]
        print("  %-10s %s" % (kind, "  ".join("%s %d" % (o, c[o]) for o in ("ok", "error", "long", "crash", "hang") if o in c)))
    if counts.get("crash") or counts.get("hang"):
        print("crashes and hangs saved in %s" % args.out)
    return 1 if counts.get("crash") else 0


if __name__ == "__main__":
    sys.exit(main())
