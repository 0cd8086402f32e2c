#!/usr/bin/env python3
"""Prints the longest functions of the library and tools (README "Layout": none over 100 lines).

    python3 tools/longest_functions.py [--top 10] [--max 100] [DIR ...]
    (default DIRs: every library and tools folder, core kernels io pipelines engine tools python/src)

The check a reviewer runs is `python3 tools/longest_functions.py --max 100`.

A function is a brace block opened at namespace or class scope after a
parameter list; its length runs from the line of its name to its closing
brace (lambdas and local classes count toward the function holding them).
`extern "C" { ... }` blocks are scopes like namespaces. Comments and string
literals are blanked first. With --max, exits 1 when a function is longer and
lists those functions."""
import argparse
import os
import re
import sys

# Scopes that hold declarations, not code. String literals are blanked before
# matching, so `extern "C" {` reads as `extern     {`.
CONTAINERS = r'\b(namespace|class|struct|union|enum|extern)\b'
KEYWORDS_BLOCK = re.compile(CONTAINERS + r'[^;{()]*$')
CONTROL = re.compile(r'\b(if|for|while|switch|catch|do|else|try)\s*$')


def strip(text):
    """Blanks comments and string/char literals, keeping newlines."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            i = j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if m:
                end = text.find(')' + m.group(1) + '"', i)
                end = n if end < 0 else end + len(m.group(1)) + 2
                out.append(re.sub(r'[^\n]', ' ', text[i:end]))
                i = end
            else:
                out.append(c)
                i += 1
        elif c in '"\'':
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == '\\' else 1
            out.append(' ' * (min(j, n - 1) + 1 - i))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def functions(path):
    text = strip(open(path, encoding='utf-8', errors='replace').read())
    results = []
    stack = []  # 'container' | 'function' | 'block'
    head_start = 0  # index where the current declaration head began
    fn_open = None
    i = 0
    for i, c in enumerate(text):
        if c in ';':
            if not stack or stack[-1] == 'container':
                head_start = i + 1
        elif c == '{':
            inside_fn = 'function' in stack
            head = text[head_start:i]
            if inside_fn:
                stack.append('block')
            elif KEYWORDS_BLOCK.search(head.strip().split('\n')[-1] if head.strip() else '') or \
                    re.search(CONTAINERS, head) and ')' not in head:
                stack.append('container')
                head_start = i + 1
            elif ')' in head and not CONTROL.search(head.rstrip()) and not re.search(r'=\s*$', head.rstrip()):
                stack.append('function')
                # the name line: first non-blank line of the head
                pre = text[:head_start]
                off = len(head) - len(head.lstrip())
                start_line = pre.count('\n') + head[:off].count('\n') + 1
                m = re.search(r'([\w:~]+(?:operator\S*)?)\s*\(', head)
                fn_open = (start_line, m.group(1) if m else '?')
            else:
                stack.append('block')
        elif c == '}':
            if stack:
                kind = stack.pop()
                if kind == 'function' and 'function' not in stack and fn_open:
                    end_line = text[:i].count('\n') + 1
                    results.append((end_line - fn_open[0] + 1, path, fn_open[0], fn_open[1]))
                    fn_open = None
            if not stack or stack[-1] == 'container':
                head_start = i + 1
    return results


DEFAULT_DIRS = ['core', 'kernels', 'io', 'pipelines', 'engine', 'tools', 'python/src']


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('dirs', nargs='*', default=DEFAULT_DIRS)
    ap.add_argument('--top', type=int, default=10)
    ap.add_argument('--max', type=int, default=0)
    a = ap.parse_args()
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..')
    found = []
    for d in a.dirs:
        base = d if os.path.isabs(d) else os.path.join(root, d)
        for dp, _, fs in os.walk(base):
            for f in fs:
                if f.endswith(('.cpp', '.hpp', '.h')):
                    found += functions(os.path.join(dp, f))
    found.sort(key=lambda r: -r[0])
    for length, path, line, name in found[:a.top]:
        print(f'{length:5d}  {os.path.relpath(path, root)}:{line}  {name}')
    if a.max and found and found[0][0] > a.max:
        over = [r for r in found if r[0] > a.max]
        for length, path, line, name in over[a.top:]:
            print(f'{length:5d}  {os.path.relpath(path, root)}:{line}  {name}')
        print(f'{len(over)} function(s) over {a.max} lines', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
