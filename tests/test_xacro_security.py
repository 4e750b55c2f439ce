"""The expression sandbox and the resource limits of urdftk's xacro expander.

Each exploit is first shown to work against stock xacro 2.1.1 where it does (the oracle proves
the test input is a real attack), then shown to be refused by ours with a clear error.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
import textwrap
import time

import pytest

from urdftk.errors import XacroError
from urdftk.xacro import process_string
from urdftk.xacro._eval import SandboxError

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def doc(body: str) -> str:
    return f"<r {NS}>{body}</r>"


def stock_output(text: str, tmp_path) -> subprocess.CompletedProcess:
    path = tmp_path / "in.xacro"
    path.write_text(text)
    return subprocess.run(
        [str(Path_xacro()), str(path)], capture_output=True, text=True, timeout=60, cwd=tmp_path
    )


def Path_xacro():
    from pathlib import Path

    exe = Path(sys.executable).with_name("xacro")
    assert exe.is_file(), "stock xacro (the oracle) is not installed in the venv"
    return exe


def refused(text: str, *names: str) -> str:
    with pytest.raises(XacroError) as info:
        process_string(text, filename="evil.xacro")
    msg = str(info.value)
    assert msg.startswith("evil.xacro:"), msg
    for name in names:
        assert name in msg, msg
    return msg


# -- the three exploits of the issue: they run code in stock, not in ours ------------------------
def test_lambda_globals_exploit(tmp_path):
    marker = tmp_path / "pwned"
    evil = doc(f"${{(lambda:xacro.load_yaml.__globals__['os'].system('touch {marker}'))()}}")
    stock_output(evil, tmp_path)
    assert marker.exists(), "the oracle no longer shows the exploit"
    marker.unlink()
    msg = refused(evil, "__globals__")
    assert "sandbox" in msg
    assert not marker.exists()


def test_eval_substitution_exploit(tmp_path):
    marker = tmp_path / "pwned"
    code = f"open('{marker}', 'w').write('x')"
    evil = doc(f'<xacro:property name="p" value="{code}"/><a v="$(eval ${{p}})"/>')
    stock_output(evil, tmp_path)
    assert marker.exists(), "the oracle no longer shows the exploit"
    marker.unlink()
    refused(evil, "open")
    assert not marker.exists()


def test_yaml_tag_exploit(tmp_path):
    marker = tmp_path / "pwned"
    payload = f"(lambda: xacro.load_yaml.__globals__['os'].system('touch {marker}'))()"
    (tmp_path / "evil.yaml").write_text(f'a: !radians "{payload}"\n')
    evil = doc(f'<xacro:property name="v" value="${{xacro.load_yaml(\'{tmp_path / "evil.yaml"}\')}}"/>${{v}}')
    stock_output(evil, tmp_path)
    assert marker.exists(), "the oracle no longer shows the exploit"
    marker.unlink()
    refused(evil, "__globals__")
    assert not marker.exists()


def test_yaml_tag_dunder_refused(tmp_path):
    (tmp_path / "evil.yaml").write_text("a: !degrees __import__('os').getpid()\n")
    refused(doc(f"${{xacro.load_yaml('{tmp_path / 'evil.yaml'}')}}"), "__import__")


def test_yaml_tags_still_work(tmp_path):
    (tmp_path / "u.yaml").write_text("a: !degrees 90\nb: !millimeters 2*5\nc: !radians pi/2\n")
    out = process_string(
        doc(
            f'<xacro:property name="y" value="${{xacro.load_yaml(\'{tmp_path / "u.yaml"}\')}}"/>'
            '<v a="${y.a}" b="${y.b}" c="${y[\'c\']}"/>'
        )
    )
    assert '<v a="1.5707963267948966" b="0.01" c="1.5707963267948966"/>' in out


# -- further ways out -------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("expr", "name"),
    [
        ("''.__class__.__mro__[1].__subclasses__()", "__class__"),
        ("[].__class__.__base__.__subclasses__()", "__class__"),
        ("python.type(1).mro()", "mro"),
        ("getattr(1, 'real')", "getattr"),
        ("vars()", "vars"),
        ("python.vars(xacro)", "vars"),
        ("globals()", "globals"),
        ("open('/etc/passwd').read()", "open"),
        ("__import__('os')", "__import__"),
        ("__builtins__", "__builtins__"),
        ("(x for x in [1]).gi_frame.f_back", "gi_frame"),
        ("(lambda: 0).func_globals", "func_globals"),
        ("xacro.load_yaml.func_globals", "func_globals"),
        ("math.sin.self", "self"),
        ("[(y := 1)]", "NamedExpr"),
        ("python.type(python.type(1))(1)", "type"),
        ("10 ** 10 ** 10", "too large"),
    ],
)
def test_refused_expressions(expr, name):
    msg = refused(doc(f'<a v="${{{expr}}}"/>'), name)
    assert "refused by the xacro sandbox" in msg


@pytest.mark.parametrize("method", ["format", "format_map"])
@pytest.mark.parametrize("fmt", ["{0.__class__}", "{0.real}", "{a.__class__.__mro__}", "{0:{0.__class__}}"])
def test_format_string_tricks_refused(method, fmt):
    call = "f.format(1, a=1)" if method == "format" else "f.format_map(dict(a=1))"
    msg = refused(doc(f'<xacro:property name="f" value="{fmt}"/><a v="${{{call}}}"/>'), "format string")
    assert "refused" in msg
    msg = refused(
        doc(
            f'<xacro:property name="f" value="{fmt}"/><a v="${{str.{method}(f, 1, a=1)}}"/>'
            if method == "format"
            else f'<xacro:property name="f" value="{fmt}"/><a v="${{str.format_map(f, dict(a=1))}}"/>'
        ),
        "format string",
    )


def test_safe_language_still_works():
    out = process_string(
        doc(
            '<xacro:property name="f" value="{0:.2f}-{name}"/>'
            '<a v="${f.format(3.14159, name=\'x\')}" w="${[i*i for i in python.range(4)]}" '
            "x=\"${(lambda s: s.upper())('ab')}\" y=\"${dict(a=1)['a'] if True else 0}\" "
            'z="${\'-\'.join(str(c) for c in [1, 2])}" u="${math.pi:.3}" />'.replace(
                "${math.pi:.3}", "${'%.3f' % pi}"
            )
        )
    )
    assert '<a u="3.142" v="3.14-x" w="[0, 1, 4, 9]" x="AB" y="1" z="1-2"/>' in out


# -- XML bombs and expansion bombs -------------------------------------------------------------
LAUGHS = textwrap.dedent("""\
    <?xml version="1.0"?>
    <!DOCTYPE lolz [
     <!ENTITY lol "lol">
     <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
     <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
     <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
     <!ENTITY lol9 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
    ]>
    <robot>&lol9;</robot>
""")


def test_billion_laughs_entities_rejected():
    with pytest.raises(XacroError, match="DOCTYPE"):
        process_string(LAUGHS, filename="lolz.xacro")


def test_external_entity_rejected(tmp_path):
    evil = '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]><r>&x;</r>'
    with pytest.raises(XacroError, match="DOCTYPE"):
        process_string(evil)


def _laughs_properties() -> str:
    props = ['<xacro:property name="p0" value="lol"/>']
    for k in range(1, 12):
        ref = "${p" + str(k - 1) + "}"
        props.append(f'<xacro:property name="p{k}" value="{ref * 10}"/>')
    return doc("".join(props) + "<a>${p11}</a>")


def _nested_macros(fanout: int, levels: int, pad: int) -> str:
    parts = ['<xacro:macro name="m0"><link name="l"/></xacro:macro>']
    for k in range(1, levels):
        parts.append(f'<xacro:macro name="m{k}">' + f"<xacro:m{k - 1}/>" * fanout + "</xacro:macro>")
    filler = "<!-- " + "x" * 200 + " -->\n"
    text = doc("".join(parts) + filler * pad + f"<xacro:m{levels - 1}/>")
    return text


def _deep_chain(n: int) -> str:
    parts = ['<xacro:macro name="m0"><link name="l"/></xacro:macro>']
    parts += [f'<xacro:macro name="m{k}"><x><xacro:m{k - 1}/></x></xacro:macro>' for k in range(1, n)]
    return doc("".join(parts) + f"<xacro:m{n - 1}/>")


BOMBS = {
    "property_laughs": lambda: _laughs_properties(),
    "macro_fanout_1MB": lambda: _nested_macros(10, 12, 5000),
    "macro_chain_1MB": lambda: _deep_chain(20000),
    "deep_xml_1MB": lambda: doc("<a>" * 150000 + "</a>" * 150000),
    "entity_laughs": lambda: LAUGHS,
}


@pytest.mark.timeout(60)
@pytest.mark.parametrize("kind", list(BOMBS))
def test_bombs_end_fast_with_bounded_memory(kind, tmp_path):
    text = BOMBS[kind]()
    if kind != "property_laughs" and kind != "entity_laughs":
        assert len(text) >= 1_000_000, len(text)
    path = tmp_path / "bomb.xacro"
    path.write_text(text)
    code = textwrap.dedent(f"""
        import sys
        from urdftk.xacro import process_file
        from urdftk.errors import XacroError
        try:
            process_file({str(path)!r})
            print("finished")
        except XacroError as e:
            print("failed:", str(e).splitlines()[0][:200])
        # Peak RSS of this process's own memory map (VmHWM). ru_maxrss would not do: Linux keeps
        # it across fork+exec, so a child of a big pytest process reports the parent's peak.
        with open("/proc/self/status") as fh:
            hwm = next(line for line in fh if line.startswith("VmHWM:"))
        print("maxrss_kb", int(hwm.split()[1]))
    """)
    t0 = time.monotonic()
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=50)
    elapsed = time.monotonic() - t0
    assert run.returncode == 0, run.stderr[-2000:]
    assert elapsed < 10, f"{kind} took {elapsed:.1f}s"
    lines = run.stdout.splitlines()
    assert lines[0].startswith(("finished", "failed:")), run.stdout
    rss_mb = int(lines[-1].split()[1]) / 1024
    assert rss_mb < 600, f"{kind} used {rss_mb:.0f} MB"
    if kind != "deep_xml_1MB":
        assert lines[0].startswith("failed:"), lines[0]


def test_sandbox_error_is_xacro_error():
    assert issubclass(SandboxError, XacroError)
    assert resource  # used by the bomb subprocess
    assert os
