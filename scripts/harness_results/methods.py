"""Methods as data: `study.py card|accuracy|ablation --method 'NAME=KEY=JSON,KEY=JSON'` (repeatable)
adds a method of the user's beside the built-in ones. NAME names its rows (letters, digits and
`_ . + -`); each KEY=JSON is a `harness run --set` override (KEY a scene key path such as
`contacts.0.force`, JSON a JSON literal or a bare word, which the harness takes as a string). The
pieces are split on the commas outside brackets, braces and quotes, so that a list or an object
stays whole: `k500d=contacts.0.force={"stiffness":500,"damping":0.1},references.solvers=["cgal","fcl"]`.

A method's overrides are recorded where its rows go (`overrides`, in the same KEY=JSON,KEY=JSON
form: `parse` reads a cell back) beside its name (`method`).
"""

import collections
import hashlib
import json
import re

NAME = re.compile(r"^[A-Za-z0-9_.+-]+$")
KEY = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z0-9_]+)*$")
WORD = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")  # a bare word: a string to the harness (core/scene/document.cpp)

Method = collections.namedtuple("Method", "name sets")


class MethodError(ValueError):
    """A --method that cannot be read; its message names the bad piece (one line)."""


def split_top(text):
    """`text` split on the commas outside brackets, braces and double quotes (a backslash escapes
    in a string). MethodError on an unbalanced bracket, brace or quote."""
    pieces, depth, cur, quoted, escaped = [], [], [], False, False
    close = {"[": "]", "{": "}"}
    for ch in text:
        if quoted:
            cur.append(ch)
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                quoted = False
            continue
        if ch == '"':
            quoted = True
        elif ch in close:
            depth.append(close[ch])
        elif ch in "]}":
            if not depth or depth.pop() != ch:
                raise MethodError("%r: unbalanced %r" % (text, ch))
        elif ch == "," and not depth:
            pieces.append("".join(cur))
            cur = []
            continue
        cur.append(ch)
    if quoted:
        raise MethodError("%r: unclosed quote" % text)
    if depth:
        raise MethodError("%r: unclosed %r" % (text, {"]": "[", "}": "{"}[depth[-1]]))
    pieces.append("".join(cur))
    return pieces


def _no_constant(c):
    raise ValueError(c)


def check_set(piece):
    """One KEY=JSON piece as `harness run --set` takes it; MethodError naming it when it is not."""
    key, eq, value = piece.partition("=")
    if not eq:
        raise MethodError("%r: expected KEY=JSON" % piece)
    if not KEY.match(key):
        raise MethodError("%r: %r is not a scene key path (as contacts.0.force)" % (piece, key))
    if not WORD.match(value):
        try:
            json.loads(value, parse_constant=_no_constant)  # NaN, Infinity: not JSON to the harness
        except ValueError:
            raise MethodError("%r: the value %r is not JSON (strings in quotes; a bare word is a string)"
                              % (piece, value)) from None
    return piece


def parse(spec):
    """A Method (name, [KEY=JSON, ...]) from 'NAME=KEY=JSON,KEY=JSON'; MethodError naming the bad
    piece."""
    name, eq, rest = spec.partition("=")
    if not eq or not name:
        raise MethodError("%r: expected NAME=KEY=JSON,KEY=JSON" % spec)
    if not NAME.match(name):
        raise MethodError("%r: the name %r may hold letters, digits and _ . + - only" % (spec, name))
    if not rest.strip():
        raise MethodError("%r: no KEY=JSON after the name" % spec)
    try:
        return Method(name, [check_set(p.strip()) for p in split_top(rest)])
    except MethodError as e:
        raise MethodError("%s (in %r)" % (e, spec)) from None


def parse_all(specs, taken=()):
    """Every --method (a list of specs) as Methods; MethodError on a bad one, on a name given twice
    or on one of the names `taken` (the built-in methods')."""
    out = []
    for spec in specs or []:
        m = parse(spec)
        if m.name in taken or any(o.name == m.name for o in out):
            raise MethodError("%r: the name %r is %s" % (spec, m.name, "taken by a built-in method" if m.name in taken
                                                          else "given twice"))
        out.append(m)
    return out


def text(sets):
    """Overrides as one cell: KEY=JSON,KEY=JSON (parse's form)."""
    return ",".join(sets)


def folder(m, before=()):
    """The run folder's name of a method: its name and a hash of its overrides and of the overrides
    `before` them (study.py card's --set): changed overrides are a new run, not a cached one."""
    return "method-%s-%s" % (m.name, hashlib.sha1(text(list(before) + m.sets).encode()).hexdigest()[:8])


def value(sets, key, default=None):
    """The JSON value the last override of `key` in `sets` gives it (a bare word: the string),
    `default` where none does."""
    out = default
    for s in sets:
        k, _, v = s.partition("=")
        if k == key:
            try:
                out = json.loads(v)
            except ValueError:
                out = v
    return out
