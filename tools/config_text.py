"""Edits of AsynEVO configuration text (config/*.yaml, a run folder's config.yaml) that keep its
comments and layout: `section.key=value` overrides and swapping the backend section. Used by the
evaluation matrix's replays (tools/matrix_run.py)."""

import re


def override_yaml(text, overrides, source):
    """The YAML text with `section.key=value` overrides applied to two-level keys (the layout of
    config/*.yaml and of a run folder's config.yaml); an unknown section or key is an error."""
    lines = text.split("\n")
    for item in overrides:
        m = re.fullmatch(r"(\w+)\.(\w+)=(.+)", item)
        if not m:
            raise SystemExit("--set %r: expected section.key=value" % item)
        section, key, value = m.groups()
        current, done = None, False
        for i, line in enumerate(lines):
            head = re.match(r"^(\w+):", line)
            if head:
                current = head.group(1)
            if current == section and re.match(r"^  %s:" % re.escape(key), line):
                lines[i] = "  %s: %s" % (key, value)
                done = True
        if not done:
            raise SystemExit("--set %r: no key %s in section %s of %s" % (item, key, section, source))
    return "\n".join(lines)


def split_section(text, section):
    """(before, block, after): the text cut around a top-level section (its header line up to the next
    top-level key); an absent section is an error."""
    lines = text.split("\n")
    start = next((i for i, l in enumerate(lines) if l.startswith(section + ":")), None)
    if start is None:
        raise SystemExit("no section %s in the configuration" % section)
    end = next((i for i in range(start + 1, len(lines)) if re.match(r"^\w+:", lines[i])), len(lines))
    return "\n".join(lines[:start]), "\n".join(lines[start:end]), "\n".join(lines[end:])


def without_backend(config):
    """The configuration text the recorded tracks depend on: everything but the backend section (the
    frontend never waits for or reads from the backend, so its tracks do not depend on it)."""
    before, _, after = split_section(config, "backend")
    return before + "\n" + after


def with_backend_of(config, source):
    """`config` with its backend section replaced by the one of `source`."""
    before, _, after = split_section(config, "backend")
    return "\n".join(part for part in (before, split_section(source, "backend")[1].rstrip("\n"), after) if part)
