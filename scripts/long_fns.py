#!/usr/bin/env python3
"""Lists the functions longer than a limit (default 80 lines, signature to closing
brace) in the Rust files under the given folders (default src/), longest first.

Usage: scripts/long_fns.py [--limit N] [--tests] [FOLDER...]

Test modules (`#[cfg(test)] mod ...`) are skipped unless --tests is given. Braces in
strings, chars and comments are skipped too, well enough for this code base: raw
strings and nested block comments are not parsed.
"""
import os
import re
import sys

FN = re.compile(r'^\s*(?:pub(?:\([^)]*\))?\s+)?(?:const\s+)?(?:async\s+)?(?:unsafe\s+)?(?:extern\s+"[^"]*"\s+)?fn\s+(\w+)')


def code_only(line):
    """The line without string and char literals and line comments."""
    line = re.sub(r'"(?:\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(?:\\.|[^'\\])'", "''", line)
    return line.split('//', 1)[0]


def functions(path, with_tests):
    lines = open(path, encoding='utf-8').read().split('\n')
    out, i = [], 0
    while i < len(lines):
        if not with_tests and lines[i].strip() == '#[cfg(test)]' and i + 1 < len(lines) and re.match(r'\s*mod \w+', lines[i + 1]):
            break  # test modules sit at the end of a file
        m = FN.match(lines[i])
        if m:
            depth, opened, j = 0, False, i
            while j < len(lines):
                code = code_only(lines[j])
                if not opened and ';' in code and '{' not in code:
                    break  # a declaration without a body
                for c in code:
                    if c == '{':
                        depth, opened = depth + 1, True
                    elif c == '}':
                        depth -= 1
                if opened and depth == 0:
                    out.append((j - i + 1, path, i + 1, m.group(1)))
                    break
                j += 1
        i += 1
    return out


def main(args):
    limit, with_tests, roots = 80, False, []
    it = iter(args)
    for a in it:
        if a == '--limit':
            limit = int(next(it))
        elif a == '--tests':
            with_tests = True
        else:
            roots.append(a)
    found = []
    for root in roots or ['src']:
        for folder, _, names in os.walk(root):
            for name in sorted(names):
                if name.endswith('.rs'):
                    found += functions(os.path.join(folder, name), with_tests)
    for length, path, line, name in sorted(found, key=lambda f: (-f[0], f[1], f[2])):
        if length > limit:
            print(f'{length:5} {path}:{line} {name}')


if __name__ == '__main__':
    main(sys.argv[1:])
