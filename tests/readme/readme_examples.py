"""Every command in the code blocks of README.md and docs/*.md runs, so the
examples cannot rot.

The documents are README.md and then every docs/*.md in name order; their
fenced blocks are read in order:
- ```sh, ```bash, ```shell: every line that is not blank or a comment is a
  command (a trailing backslash continues it on the next line), unless the
  block starts with `#!`: then it shows a script file, which is not run;
- ```python: the block is one program; a block of `>>>` prompts runs as a
  doctest: the prompted lines (`>>> `, `... `) are the program and every
  other line is the output it must print, exactly;
- untagged (or ```text) blocks show output: only their lines that start
  with `$ ` or with a program (build/..., ./..., PYTHONPATH=..., cmp, sudo,
  cmake, ctest, python3) are commands;
- ```c++, ```cpp, ```cmake: code that another test builds; each must be
  listed in the data file (skip, naming that test);
- other blocks (```toml) are file contents and are not run.

All commands run in that order in one scratch folder, so a block can use
an earlier block's output. The folder holds copies of scenarios/ and
models/ (edited there when the data file says so), `build` as a link to the
build tree and `sim`, `bench` as links to the source folders that hold
scripts the documents run; nothing is written into the source tree. A command
must exit 0 (or the code the data file expects) and print what the data file
expects on stdout or stderr.

The data file (overrides.txt next to this script) lists, one a line,
`KIND | TEXT | VALUE`, where TEXT is the command as the document shows
it (continuations joined, trailing shell comment dropped, runs of
white space as one space), or the first line of a python/c++/cmake block:
  skip    | TEXT | why it cannot run here
  append  | TEXT | arguments added at the end
  replace | TEXT | OLD -> NEW   (OLD must occur in the command)
  exit    | TEXT | the expected exit code
  stdout  | TEXT | a fragment the command must print on stdout
  stderr  | TEXT | a fragment the command must print on stderr
  edit    | FILE | OLD -> NEW   (in the scratch copy; OLD must occur)
  file    | FILE | contents written into the scratch folder (\\n: newline)
Every group of entries starts with a comment saying why. An entry applies
to the command wherever a document shows it. The test fails when a command
is neither run nor skipped, when an entry matches no command of any
document, and when an edit or replacement finds nothing to change.

Usage: readme_examples.py README DATA SOURCE_DIR BUILD_DIR [--shard K/N]
                          [--without-python] [--without-bench]
(the docs/*.md beside README are read too; with --shard K/N only the K-th
of every N documents, counted from 1 in the order above, runs, in a scratch
folder of its own, so that N tests share the documents; the data file is
checked against all of them in each)
(a build without the Python module or the benchmarks: their commands are
reported as not run)
"""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

TIMEOUT_S = 120
SHELL_TAGS = {"sh", "bash", "shell"}
PYTHON_TAGS = {"python"}
CODE_TAGS = {"c++", "cpp", "cmake"}
OUTPUT_TAGS = {"", "text"}
FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
# In an output block, a line that starts like this is a command.
COMMAND_START = re.compile(r"^(build/|\./|PYTHONPATH=|/usr/bin/python3 |python3 |cmp |sudo |cmake |ctest )")
KINDS = {"skip", "append", "replace", "exit", "stdout", "stderr", "edit", "file"}
FILE_KINDS = {"edit", "file"}
# What the commands need from the source tree, read only.
LINKED_SOURCE_FOLDERS = ["sim", "bench"]
COPIED_SOURCE_FOLDERS = ["scenarios", "models"]


class Unit:
    """One thing a document shows to run: a shell command or a program."""

    def __init__(self, kind, key, code, where):
        self.kind = kind  # "shell", "python" or "code"
        self.key = key
        self.code = code
        self.where = where  # "DOCUMENT:LINE"


def squeeze(text):
    return " ".join(text.split())


def without_shell_comment(line):
    """The line up to a `#` that starts a comment (outside quotes)."""
    quote = None
    for i, c in enumerate(line):
        if quote:
            if c == quote:
                quote = None
        elif c in "'\"":
            quote = c
        elif c == "#" and (i == 0 or line[i - 1].isspace()):
            return line[:i]
    return line


def shell_units(lines, name, first_line, is_command):
    """The commands among lines, continuations joined."""
    units = []
    pending, start = None, 0
    for offset, raw in enumerate(lines):
        text = raw.rstrip()
        if pending is None:
            command = is_command(text)
            if command is None:
                continue
            pending, start = command, first_line + offset
        else:
            pending += "\n" + text
        if pending.endswith("\\"):
            continue
        joined = re.sub(r"\\\n\s*", " ", pending)
        units.append(Unit("shell", squeeze(without_shell_comment(joined)), joined, f"{name}:{start}"))
        pending = None
    if pending is not None:
        raise SystemExit(f"{name}:{start}: a command ends with a backslash")
    return units


def sh_command(text):
    stripped = text.strip()
    return None if not stripped or stripped.startswith("#") else stripped


def output_block_command(prompted):
    def is_command(text):
        stripped = text.strip()
        if prompted:
            return stripped[2:] if stripped.startswith("$ ") else None
        return stripped if COMMAND_START.match(stripped) else None
    return is_command


# A block of `>>>` prompts runs as a doctest: every output line the
# document shows must be what the statement prints, character for character.
DOCTEST_PROGRAM = """import doctest, sys
block = {block!r}
test = doctest.DocTestParser().get_doctest(block, {{}}, {name!r}, {name!r}, {line})
runner = doctest.DocTestRunner(verbose=False)
runner.run(test, out=sys.stdout.write)
sys.exit(1 if runner.failures else 0)
"""


def python_unit(lines, name, first_line):
    if any(l.startswith(">>> ") for l in lines):
        code = DOCTEST_PROGRAM.format(block="\n".join(lines) + "\n", name=name,
                                      line=first_line - 1)
    else:
        code = "\n".join(lines) + "\n"
    return Unit("python", squeeze(lines[0]), code, f"{name}:{first_line}")


def document_units(path, name):
    """The units of one document; name is its path in the source tree."""
    lines = open(path, encoding="utf-8").read().split("\n")
    units, i = [], 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        if not fence:
            i += 1
            continue
        indent, tag = fence.group(1), fence.group(2).lower()
        end = i + 1
        while end < len(lines) and not FENCE.match(lines[end]):
            end += 1
        if end == len(lines):
            raise SystemExit(f"{name}:{i + 1}: code block not closed")
        body = [l[len(indent):] if l.startswith(indent) else l for l in lines[i + 1:end]]
        first = i + 2  # the document's line of the block's first line
        if tag in SHELL_TAGS:
            if not body or not body[0].startswith("#!"):
                units += shell_units(body, name, first, sh_command)
        elif tag in OUTPUT_TAGS:
            prompted = any(l.strip().startswith("$ ") for l in body)
            units += shell_units(body, name, first, output_block_command(prompted))
        elif tag in PYTHON_TAGS:
            units.append(python_unit(body, name, first))
        elif tag in CODE_TAGS:
            units.append(Unit("code", squeeze(body[0]), "", f"{name}:{first}"))
        i = end + 1
    return units


def read_entries(path):
    """[(kind, key, value, line)]; every group of entries follows a comment."""
    entries, commented = [], False
    for number, raw in enumerate(open(path, encoding="utf-8"), 1):
        line = raw.rstrip("\n")
        if not line.strip():
            commented = False
            continue
        if line.startswith("#"):
            commented = True
            continue
        kind, sep, rest = line.partition(" | ")
        key, sep2, value = rest.rpartition(" | ")
        where = f"{path}:{number}"
        if not sep or not sep2 or kind.strip() not in KINDS:
            raise SystemExit(f"{where}: expected `KIND | TEXT | VALUE` with KIND one of "
                             f"{', '.join(sorted(KINDS))}")
        if not commented:
            raise SystemExit(f"{where}: entry without a comment above its group saying why")
        entries.append((kind.strip(), squeeze(key), value.strip(), where))
    return entries


def old_new(value, where):
    old, sep, new = value.partition(" -> ")
    if not sep or not old:
        raise SystemExit(f"{where}: expected `OLD -> NEW`")
    return old, new


def make_scratch(scratch, source, build, entries):
    for folder in COPIED_SOURCE_FOLDERS:
        shutil.copytree(os.path.join(source, folder), os.path.join(scratch, folder))
    for folder in LINKED_SOURCE_FOLDERS:
        os.symlink(os.path.join(source, folder), os.path.join(scratch, folder))
    os.symlink(build, os.path.join(scratch, "build"))
    for kind, name, value, where in entries:
        path = os.path.join(scratch, name)
        if kind == "file":
            with open(path, "w") as f:
                f.write(value.replace("\\n", "\n"))
        elif kind == "edit":
            old, new = old_new(value, where)
            text = open(path).read() if os.path.isfile(path) else ""
            if old not in text:
                raise SystemExit(f"{where}: {old!r} is not in {name}; update the entry")
            with open(path, "w") as f:
                f.write(text.replace(old, new.replace("\\n", "\n")))


def command_to_run(unit, entries):
    # A shell command runs as its README TEXT: continuations joined, the
    # comment dropped (so that appended arguments are not commented out).
    code = unit.key if unit.kind == "shell" else unit.code
    for kind, key, value, where in entries:
        if key != unit.key:
            continue
        if kind == "replace":
            old, new = old_new(value, where)
            if old not in code:
                raise SystemExit(f"{where}: {old!r} is not in the command; update the entry")
            code = code.replace(old, new)
        elif kind == "append":
            code += " " + value
    return code


def run(unit, code, scratch, env):
    argv = ["bash", "-e", "-o", "pipefail", "-c", code] if unit.kind == "shell" else [sys.executable, "-"]
    stdin = subprocess.DEVNULL if unit.kind == "shell" else subprocess.PIPE
    child = subprocess.Popen(argv, cwd=scratch, env=env, stdin=stdin, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = child.communicate(None if unit.kind == "shell" else code, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        os.killpg(child.pid, signal.SIGKILL)
        out, err = child.communicate()
        return None, out, err
    return child.returncode, out, err


def tail(text, lines=15):
    return "\n".join("    " + l for l in text.rstrip().split("\n")[-lines:])


def main():
    readme, data, source, build = (os.path.abspath(a) for a in sys.argv[1:5])
    # What this build leaves out: {flag: (does a unit need it, why not run)}.
    absent = {
        "--without-python": (lambda unit, code: unit.kind == "python" or "build/sim/python" in code,
                             "the Python module is not built, or not importable in this build"),
        "--without-bench": (lambda unit, code: code.startswith("build/bench/"),
                            "the benchmarks are not built"),
    }
    flags = sys.argv[5:]
    shard, shards = 1, 1
    if "--shard" in flags:
        at = flags.index("--shard")
        shard, shards = (int(n) for n in flags[at + 1].split("/"))
        del flags[at:at + 2]
        if not 1 <= shard <= shards:
            raise SystemExit(f"--shard {shard}/{shards}: K must be in [1, N]")
    for flag in flags:
        if flag not in absent:
            raise SystemExit(f"unknown option {flag} (allowed: {', '.join(absent)})")
    # README.md, then every docs/*.md by name.
    documents = [readme] + sorted(glob.glob(os.path.join(os.path.dirname(readme), "docs", "*.md")))
    units_of = {path: document_units(path, os.path.relpath(path, os.path.dirname(readme)))
                for path in documents}
    units = [unit for path in documents for unit in units_of[path]]
    entries = read_entries(data)
    keys = {u.key for u in units}
    failures = []
    for kind, key, value, where in entries:
        if kind not in FILE_KINDS and key not in keys:
            failures.append(f"{where}: no command of the documents reads `{key}`; update or remove the entry")
    for unit in units:
        kinds = {k for k, key, _, _ in entries if key == unit.key}
        if unit.kind == "code" and "skip" not in kinds:
            failures.append(f"{unit.where}: `{unit.key}` is code another test builds; "
                            f"list it in {os.path.basename(data)} as skipped, naming that test")
        if "skip" in kinds and len(kinds) > 1:
            failures.append(f"{unit.where}: `{unit.key}` is skipped and also overridden")
    if failures:
        raise SystemExit("\n".join(failures))
    shard_documents = documents[shard - 1::shards]
    shard_units = [unit for path in shard_documents for unit in units_of[path]]

    scratch = tempfile.mkdtemp(prefix="readme_examples_")
    # Commands say their own PYTHONPATH; a python block runs in the
    # interpreter the README starts with PYTHONPATH=build/sim/python.
    # Nothing writes bytecode beside the linked sources.
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    for name in ("PYTHONPATH", "TERM"):
        env.pop(name, None)
    python_env = dict(env, PYTHONPATH="build/sim/python")
    ran = skipped = 0
    try:
        make_scratch(scratch, source, build, entries)
        for kind, name, _, where in entries:
            if kind == "file" and not any(name in command_to_run(u, entries) for u in units):
                failures.append(f"{where}: no command uses the file {name}; remove the entry")
        for unit in shard_units:
            mine = [(k, v) for k, key, v, _ in entries if key == unit.key]
            reasons = [v for k, v in mine if k == "skip"]
            label = f"{unit.where}: {unit.key}"
            if reasons:
                print(f"skipped  {label}\n         ({reasons[0]})")
                skipped += 1
                continue
            code = command_to_run(unit, entries)
            missing = [why for flag, (needs, why) in absent.items()
                       if flag in flags and needs(unit, code)]
            if missing:
                print(f"not run  {label} ({missing[0]})")
                skipped += 1
                continue
            started = time.monotonic()
            status, out, err = run(unit, code, scratch, python_env if unit.kind == "python" else env)
            seconds = time.monotonic() - started
            expected = int(next((v for k, v in mine if k == "exit"), 0))
            problems = []
            if status is None:
                problems.append(f"did not finish within {TIMEOUT_S} s")
            elif status != expected:
                problems.append(f"exit code {status}, expected {expected}")
            for stream, text in (("stdout", out), ("stderr", err)):
                for k, fragment in mine:
                    if k == stream and fragment not in text:
                        problems.append(f"{stream} lacks {fragment!r}")
            print(f"{'FAILED' if problems else 'ran':8} {label} ({seconds:.1f} s)")
            if unit.kind == "shell" and code != unit.key:
                print(f"         as: {code.strip()}")
            ran += 1
            if problems:
                failures.append(f"{label}: {'; '.join(problems)}\n  stdout:\n{tail(out)}\n"
                                f"  stderr:\n{tail(err)}")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    print(f"{ran} commands of {len(shard_documents)} documents run, {skipped} skipped")
    if failures:
        print("\n".join(failures), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
