"""--junit reports of check, parity, parity --random and reference (CTest: junit):
each validated against Jenkins' JUnit schema (tests/data/junit/, xmllint) and
read back with junitparser; a failure's text is what the terminal showed."""
import os
import shutil
import subprocess
import sys

import junitparser
import pytest

CLI = os.environ["SPLATREF_CLI"]
SRC = os.environ["SPLATREF_SOURCE"]
XSD = os.path.join(SRC, "tests", "data", "junit", "junit-10.xsd")


def run(*args, cwd):
    return subprocess.run([CLI, *args], cwd=cwd, capture_output=True, text=True)


def read(path):
    v = subprocess.run(["xmllint", "--noout", "--schema", XSD, str(path)], capture_output=True, text=True)
    assert v.returncode == 0, v.stderr
    x = junitparser.JUnitXml.fromfile(str(path))
    suites = list(x)
    assert len(suites) == 1
    return suites[0], list(suites[0])


def outcome(case):
    return [type(r).__name__ for r in case.result]


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    d = tmp_path_factory.mktemp("junit")
    p = run("render", "--model", "builtin:torus", "--points", "3000", "--size", "64x48", "--algo", "deferred", "--save-scene", "s.json",
            "--float", "a.pfm", "--out", "a.png", "--quiet", cwd=d)
    assert p.returncode == 0, p.stderr
    return d


def test_check_pass_and_fail(scene):
    d = scene
    p = run("check", "--scene", "s.json", "--image", "a.png", "--junit", "pass.xml", "--out", "r1", "--quiet", cwd=d)
    assert p.returncode == 0, p.stderr
    suite, cases = read(d / "pass.xml")
    assert (suite.tests, suite.failures, suite.errors) == (1, 0, 0) and outcome(cases[0]) == []
    # one float off by an ulp, with XML's special characters in the file name
    bad = d / "a<&>'\".pfm"
    shutil.copy(d / "a.pfm", bad)
    with open(bad, "r+b") as f:
        f.seek(-4, 2)
        f.write(b"\x01")
    p = run("check", "--scene", "s.json", "--image", str(bad), "--junit", "fail.xml", "--out", "r2", "--quiet", cwd=d)
    assert p.returncode == 1, p.stderr
    suite, cases = read(d / "fail.xml")
    assert (suite.tests, suite.failures) == (1, 1)
    assert cases[0].name == str(bad) + ": final colour"
    assert outcome(cases[0]) == ["Failure"]
    assert cases[0].result[0].text == p.stdout  # the terminal's lines, every one
    assert "1 of 3072 pixels fail" in cases[0].result[0].message


def test_parity_one_case_per_plane(scene):
    d = scene
    p = run("parity", "--scene", "s.json", "--junit", "same.xml", "--quiet", cwd=d)
    if p.returncode == 2 and "no device" in p.stderr.lower():
        pytest.skip(p.stderr)
    assert p.returncode == 0, p.stderr
    suite, cases = read(d / "same.xml")
    planes = int(p.stdout.split("parity deferred: ")[1].split("/")[1].split(" ")[0])
    assert suite.tests == planes + 1 and suite.failures == 0  # every plane, and the fragment counts
    p = run("parity", "--scene", "s.json", "--gl-eps", "1e-6", "--junit", "diff.xml", "--quiet", cwd=d)
    assert p.returncode == 1, p.stderr
    suite, cases = read(d / "diff.xml")
    failed = [c for c in cases if outcome(c) == ["Failure"]]
    assert failed and suite.failures == len(failed)
    shown = [l.split("first differences: ", 1)[1] for l in p.stdout.splitlines() if "first differences: " in l]
    assert shown and [c.result[0].text for c in failed[:len(shown)]] == shown  # the lines the terminal shows, in its order


def test_parity_random_one_case_per_comparison(tmp_path):
    p = run("parity", "--random", "3", "--seed", "5", "--junit", "r.xml", "--quiet", cwd=tmp_path)
    if p.returncode == 2 and "no device" in p.stderr.lower():
        pytest.skip(p.stderr)
    assert p.returncode == 0, p.stderr
    suite, cases = read(tmp_path / "r.xml")
    comparisons = int(p.stdout.split(" comparisons")[0].rsplit(" ", 1)[1])
    assert suite.tests == comparisons and suite.failures == 0 and cases[0].name.startswith("scene 0 ")


def test_reference_one_case_per_scene(tmp_path):
    p = run("reference", "--only", "torus_deferred_mgc", "--junit", str(tmp_path / "ref.xml"), "--quiet", cwd=SRC)
    assert p.returncode in (0, 77), p.stdout + p.stderr
    suite, cases = read(tmp_path / "ref.xml")
    assert suite.tests == 1 and cases[0].name == "torus_deferred_mgc" and outcome(cases[0]) == []
    line = [l for l in p.stdout.splitlines() if l.startswith("reference torus_deferred_mgc")][0]
    assert cases[0].system_out.strip() == line


def test_check_every_view(tmp_path):
    """check --camera all: one testcase a view, in the file's order; the view whose image is missing and the view whose
    image holds another view's picture fail, the others pass; the schema holds."""
    model = os.path.join(SRC, "tests", "data", "captures", "real", "donut-mipsplat.ply")
    cams = os.path.join(SRC, "tests", "data", "cameras", "donut-ring12.json")
    os.mkdir(tmp_path / "renders")
    for k in range(12):
        p = run("render", "--model", model, "--algo", "gauss-blend", "--cameras", cams, "--camera", str(k), "--size", "32x24",
                "--out", f"renders/{k:05d}.png", "--quiet", cwd=tmp_path)
        assert p.returncode == 0, p.stderr
    os.remove(tmp_path / "renders" / "00002.png")
    shutil.copy(tmp_path / "renders" / "00006.png", tmp_path / "renders" / "00005.png")
    p = run("check", "--model", model, "--algo", "gauss-blend", "--cameras", cams, "--camera", "all", "--images", "renders", "--size", "32x24",
            "--junit", "views.xml", "--quiet", cwd=tmp_path)
    assert p.returncode == 1, p.stdout + p.stderr
    suite, cases = read(tmp_path / "views.xml")
    assert len(cases) == 12
    for k, c in enumerate(cases):
        assert c.name.startswith(f"view {k + 1} of 12 (camera {k}, ring{k:02d}): "), c.name
        assert outcome(c) == (["Failure"] if k in (2, 5) else []), (k, outcome(c))
    assert "no image renders/00002.png" in cases[2].result[0].message
    assert "FAIL, " in cases[5].result[0].message
    assert suite.failures == 2 and suite.tests == 12
