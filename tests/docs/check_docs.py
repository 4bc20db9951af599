#!/usr/bin/env python3
"""Docs that cannot drift: checks the documentation against the code and the binary.

Usage (from the repository root, with Debian's /usr/bin/python3; no third-party modules):
  check_docs.py links                       every relative markdown link in docs/ and README.md resolves
                                            (file and #anchor); every page under docs/ stays under
                                            MAX_LINES; pages under docs/guide, docs/reference,
                                            docs/method and the results pages (docs/results.md,
                                            docs/results/) name no work periods
  check_docs.py reference --asynevo BIN     docs/reference/cli.md lists exactly the flags of every
                                            command's --help, with the defaults --help shows;
                                            docs/reference/config.md lists exactly the
                                            configuration keys the loader knows (the visit() lists of
                                            include/asynevo/core/config/*.hpp), with their defaults;
                                            every message in docs/guide/troubleshooting.md still exists
                                            in src/, apps/ or tools/plot_run.py
  check_docs.py guide --asynevo BIN --work DIR
                                            runs every shell block of docs/guide/*.md marked
                                            '<!-- runnable -->' in DIR (build/bin/asynevo replaced by BIN)
Exit status 0 when every check passes, 1 otherwise (each failure printed on its own line).
"""

import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import unicodedata

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MAX_LINES = 300
# Pages another branch adds; a link to them is accepted until they exist. Remove an entry once its
# page has landed.
PENDING_PAGES = set()

failures = []


def fail(message):
    failures.append(message)
    print("FAIL " + message)


def read(path):
    with open(os.path.join(ROOT, path), encoding="utf-8") as f:
        return f.read()


def markdown_files():
    files = ["README.md"]
    for folder, _, names in os.walk(os.path.join(ROOT, "docs")):
        for name in sorted(names):
            if name.endswith(".md"):
                files.append(os.path.relpath(os.path.join(folder, name), ROOT))
    return sorted(files)


def strip_code(text):
    """Text without fenced code blocks and inline code (links there are not links)."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


def github_slug(heading):
    """The anchor GitHub gives a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    out = []
    for ch in text:
        if ch in "-_ " or ch.isalnum():
            out.append(ch)
        elif unicodedata.category(ch).startswith("L") or unicodedata.category(ch).startswith("N"):
            out.append(ch)
    return "".join(out).replace(" ", "-")


def anchors(path):
    slugs, seen = set(), {}
    in_code = False
    for line in read(path).splitlines():
        if line.startswith("```"):
            in_code = not in_code
            continue
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m and not in_code:
            slug = github_slug(m.group(1))
            n = seen.get(slug, 0)
            seen[slug] = n + 1
            slugs.add(slug if n == 0 else "%s-%d" % (slug, n))
    return slugs


def check_links():
    files = markdown_files()
    link_count = 0
    for path in files:
        text = strip_code(read(path))
        for target in re.findall(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", text):
            if re.match(r"^[a-z]+:", target) or target.startswith("mailto:"):
                continue  # external
            link_count += 1
            file_part, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            if resolved in PENDING_PAGES:
                continue
            if not os.path.exists(os.path.join(ROOT, resolved)):
                fail("%s: link to %s: no such file" % (path, target))
                continue
            if anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
                fail("%s: link to %s: no heading with anchor #%s in %s" % (path, target, anchor, resolved))
    for path in files:
        if not path.startswith("docs/"):
            continue
        lines = read(path).count("\n")
        if lines > MAX_LINES:
            fail("%s: %d lines (pages stay under %d; split the page by topic)" % (path, lines, MAX_LINES))
        if not re.match(r"docs/(guide/|reference/|method/|results/|results\.md$)", path):
            continue
        for n, line in enumerate(read(path).splitlines(), 1):
            if re.search(r"\bsessions?[ -]\d", line, re.I):
                fail("%s:%d: names a numbered work period (give the date and commit instead)" % (path, n))
    print("links: %d relative links in %d pages checked" % (link_count, len(files)))


# ----------------------------------------------------------------------------------------- CLI
def help_flags(asynevo, command):
    """{flag: default shown by --help, or None} of one command."""
    out = subprocess.run([asynevo, command, "--help"], capture_output=True, text=True, check=True).stdout
    flags = {}
    for line in out.splitlines():
        m = re.match(r"^\s+((?:-\w,)?--[\w-]+)(?:\s+\S*?=(\S+))?", line)
        if m:
            flags[m.group(1).split(",")[-1]] = m.group(2)
    flags.pop("--help", None)
    return flags


def commands(asynevo):
    out = subprocess.run([asynevo, "--help"], capture_output=True, text=True, check=True).stdout
    names, in_subcommands = [], False
    for line in out.splitlines():
        if line.strip().startswith("Subcommands:"):
            in_subcommands = True
            continue
        m = re.match(r"^\s+([a-z][\w-]*)\s{2,}", line)
        if in_subcommands and m:
            names.append(m.group(1))
    return names


def documented_flags(cli_text):
    """{command: {flag: default cell}} from the tables under each '## command' heading of cli.md."""
    sections = re.split(r"^## ", cli_text, flags=re.M)
    result = {}
    for section in sections[1:]:
        name = section.splitlines()[0].strip()
        flags = {}
        for line in section.splitlines():
            if line.startswith("| `--") or line.startswith("| `-"):
                cells = line.split("|")
                for flag in re.findall(r"`(--[\w-]+)`", cells[1]):
                    flags[flag] = cells[2].strip() if len(cells) > 2 else ""
        result[name] = flags
    return result


def check_cli(asynevo):
    text = read("docs/reference/cli.md")
    documented = documented_flags(text)
    names = commands(asynevo)
    if not names:
        fail("asynevo --help lists no subcommands")
    for name in names:
        if name not in documented:
            fail("docs/reference/cli.md: no section '## %s' for the command 'asynevo %s'" % (name, name))
            continue
        actual = help_flags(asynevo, name)
        for flag in sorted(set(actual) - set(documented[name])):
            fail("docs/reference/cli.md: 'asynevo %s %s' is not documented" % (name, flag))
        for flag in sorted(set(documented[name]) - set(actual)):
            fail("docs/reference/cli.md: documents 'asynevo %s %s', which --help does not list" % (name, flag))
        for flag in sorted(set(actual) & set(documented[name])):
            shown = actual[flag]
            if shown is not None and normalize_default(shown) != normalize_default(documented[name][flag]):
                fail("docs/reference/cli.md: 'asynevo %s %s' default is '%s' in the docs, '%s' in --help"
                     % (name, flag, documented[name][flag], shown))
    for name in documented:
        if name not in names and re.match(r"^[a-z]+$", name):
            fail("docs/reference/cli.md: section '## %s' documents no command of this binary" % name)
    print("cli: %d commands compared with --help" % len(names))


# -------------------------------------------------------------------------------------- config
SECTIONS = [("sensor", "io_config.hpp", "SensorConfig"), ("input", "io_config.hpp", "InputConfig"),
            ("frontend", "frontend_config.hpp", "FrontendConfig"), ("backend", "backend_config.hpp", "BackendConfig")]


def loader_keys():
    """{section: {key: default text}} as the loader sees them: the visit() list of each section struct."""
    config_hpp = read("include/asynevo/core/config/config.hpp")
    declared = re.findall(r'v\.section\("(\w+)"', config_hpp)
    if declared != [s for s, _, _ in SECTIONS]:
        fail("config.hpp sections %s differ from the sections this check knows %s" % (declared, [s for s, _, _ in SECTIONS]))
    result = {}
    for section, header, struct in SECTIONS:
        text = read("include/asynevo/core/config/" + header)
        body = text[text.index("struct " + struct):]
        body = body[:body.index("void validate")]
        defaults = {m.group(2): m.group(3).strip() for m in re.finditer(
            r"^\s*(bool|int|double|std::string|std::vector<double>)\s+(\w+)\s*=\s*([^;]+);", body, re.M)}
        keys = {}
        for m in re.finditer(r'\bv\("(\w+)",\s*(\w+)\s*,', body):
            keys[m.group(1)] = defaults.get(m.group(2), "")
        result[section] = keys
    return result


def normalize_default(text):
    text = text.strip().strip("`").strip('"')
    text = text.replace("{", "[").replace("}", "]").replace(" ", "")
    if text.startswith("["):
        try:
            return tuple(float(x) for x in text.strip("[]").split(","))
        except ValueError:
            return text
    try:
        return float(text)
    except ValueError:
        return text


def documented_keys(config_text):
    """{section: {key: default cell}} from the tables under '## sensor' … '## backend' of config.md."""
    result = {}
    for section_text in re.split(r"^## ", config_text, flags=re.M)[1:]:
        name = section_text.splitlines()[0].strip()
        if name not in {s for s, _, _ in SECTIONS}:
            continue
        keys = {}
        for line in section_text.splitlines():
            cells = [c.strip() for c in line.split("|")]
            if len(cells) > 4 and re.fullmatch(r"`\w+`", cells[1]):
                keys[cells[1].strip("`")] = cells[3]
        result[name] = keys
    return result


def check_config():
    code = loader_keys()
    docs = documented_keys(read("docs/reference/config.md"))
    count = 0
    for section, keys in code.items():
        documented = docs.get(section)
        if documented is None:
            fail("docs/reference/config.md: no section '## %s'" % section)
            continue
        for key in sorted(set(keys) - set(documented)):
            fail("docs/reference/config.md: %s.%s is not documented" % (section, key))
        for key in sorted(set(documented) - set(keys)):
            fail("docs/reference/config.md: documents %s.%s, which the loader does not know" % (section, key))
        for key in sorted(set(keys) & set(documented)):
            count += 1
            if normalize_default(keys[key]) != normalize_default(documented[key]):
                fail("docs/reference/config.md: %s.%s default is '%s' in the docs, '%s' in the code"
                     % (section, key, documented[key], keys[key]))
    print("config: %d keys compared with the loader's lists and defaults" % count)


# ------------------------------------------------------------------------------------ messages
def code_text():
    parts = []
    for folder in ("src", "apps"):
        for base, _, names in os.walk(os.path.join(ROOT, folder)):
            for name in names:
                if name.endswith((".cpp", ".hpp")):
                    with open(os.path.join(base, name), encoding="utf-8") as f:
                        parts.append(f.read())
    parts.append(read("tools/plot_run.py"))
    text = "\n".join(parts)
    # Adjacent string literals are one string to the compiler.
    return re.sub(r'"\s*\n\s*"', "", text)


def check_messages():
    code = code_text()
    text = read("docs/guide/troubleshooting.md")
    count = 0
    for line in text.splitlines():
        if not line.startswith("| `"):
            continue
        message = re.match(r"\|\s*`([^`]+)`", line).group(1)
        count += 1
        fragments = [f for f in message.split("…") if len(f.strip()) >= 4]
        for fragment in fragments:
            if fragment not in code:
                fail("docs/guide/troubleshooting.md: message fragment '%s' is not in src/, apps/ or "
                     "tools/plot_run.py any more" % fragment)
    print("messages: %d troubleshooting messages checked against the code" % count)


# --------------------------------------------------------------------------------------- guide
def runnable_blocks():
    blocks = []
    for base, _, names in os.walk(os.path.join(ROOT, "docs", "guide")):
        for name in sorted(names):
            if not name.endswith(".md"):
                continue
            path = os.path.relpath(os.path.join(base, name), ROOT)
            for m in re.finditer(r"<!--\s*runnable\s*-->\s*\n```(?:sh|bash)\n(.*?)^```", read(path), re.S | re.M):
                blocks.append((path, m.group(1)))
    return blocks


def check_guide(asynevo, work):
    # A fresh folder each time; an existing one is removed only if this script made it.
    marker = os.path.join(work, ".check_docs_work")
    if os.path.isdir(work) and os.path.exists(marker):
        shutil.rmtree(work)
    elif os.path.exists(work) and os.listdir(work):
        fail("--work %s exists and was not made by check_docs.py: give a new folder" % work)
        return
    os.makedirs(work, exist_ok=True)
    open(marker, "w").close()
    for folder in ("tests", "config", "tools"):
        link = os.path.join(work, folder)
        if not os.path.lexists(link):
            os.symlink(os.path.join(ROOT, folder), link)
    env = dict(os.environ, ASYNEVO_TOOLS_DIR=os.path.join(ROOT, "tools"))
    commands_run = 0
    for path, block in runnable_blocks():
        for command in block.splitlines():
            command = command.split("#", 1)[0].strip() if not command.strip().startswith("#") else ""
            if not command:
                continue
            argv = shlex.split(command)
            if argv[0] == "build/bin/asynevo":
                argv[0] = asynevo
            commands_run += 1
            result = subprocess.run(argv, cwd=work, env=env, capture_output=True, text=True)
            if result.returncode != 0:
                fail("%s: '%s' exited with %d:\n%s%s" % (path, command, result.returncode, result.stdout[-2000:],
                                                       result.stderr[-2000:]))
    if commands_run == 0:
        fail("docs/guide: no runnable command found")
    print("guide: %d runnable commands run" % commands_run)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["links", "reference", "guide"])
    parser.add_argument("--asynevo", help="the asynevo binary")
    parser.add_argument("--work", help="scratch folder for the guide's commands")
    args = parser.parse_args()
    if args.mode == "links":
        check_links()
    elif args.mode == "reference":
        if not args.asynevo:
            parser.error("reference needs --asynevo")
        check_cli(os.path.abspath(args.asynevo))
        check_config()
        check_messages()
    else:
        if not args.asynevo or not args.work:
            parser.error("guide needs --asynevo and --work")
        check_guide(os.path.abspath(args.asynevo), os.path.abspath(args.work))
    if failures:
        print("%d check(s) failed" % len(failures))
        return 1
    print("all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
