"""The package itself: its generated protocol modules are what proto/ makes,
it installs offline with Debian's pip, is typed, and documents every public
name."""

from __future__ import annotations

import filecmp
import inspect
import os
import shutil
import subprocess
import sys
import tempfile

import tumble
import tumble.aio
from conftest import SOURCE


def test_the_generated_modules_are_what_proto_makes():
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([os.path.join(SOURCE, "generate.sh"), out], check=True,
                       env={**os.environ, "PROTOC": os.environ.get("PROTOC", "protoc")})
        made = os.path.join(out, "tumble", "v1")
        committed = os.path.join(SOURCE, "src", "tumble", "v1")
        names = sorted(n for n in os.listdir(made))
        assert names == sorted(n for n in os.listdir(committed) if n.endswith(("_pb2.py", "_pb2.pyi"))), \
            "clients/python/src/tumble/v1 holds other modules than proto/ makes: run clients/python/generate.sh"
        _, mismatch, errors = filecmp.cmpfiles(made, committed, names, shallow=False)
        assert not mismatch and not errors, \
            f"{mismatch + errors} differ from what proto/ makes: run clients/python/generate.sh"


def test_it_installs_offline_with_pip_and_imports_from_there():
    with tempfile.TemporaryDirectory() as work:
        # A copy, so the build leaves nothing in the source tree.
        source = os.path.join(work, "python")
        shutil.copytree(SOURCE, source, ignore=shutil.ignore_patterns("__pycache__", "build", "*.egg-info"))
        prefix = os.path.join(work, "prefix")
        # --prefix, unlike --target, counts Debian's numpy and protobuf as
        # installed: the dependencies are resolved and nothing is fetched.
        subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-index", "--no-build-isolation",
                        "--no-cache-dir", "--disable-pip-version-check", "--prefix", prefix, source], check=True)
        installed = [root for root, _, files in os.walk(prefix)
                     if os.path.basename(root) == "tumble" and "__init__.py" in files]
        assert len(installed) == 1, f"installed: {installed}"
        package = installed[0]
        assert os.path.exists(os.path.join(package, "py.typed"))
        assert os.path.exists(os.path.join(package, "v1", "protocol_pb2.pyi"))
        site = os.path.dirname(package)
        # Imported in a fresh interpreter that sees only the installed copy.
        probe = ("import sys, tumble, tumble.aio; "
                 "assert tumble.__file__.startswith(sys.argv[1]), tumble.__file__; print(tumble.__version__)")
        done = subprocess.run([sys.executable, "-c", probe, site], check=True, capture_output=True, text=True,
                              env={"PYTHONPATH": site, "PATH": os.environ.get("PATH", "")}, cwd=work)
        assert done.stdout.strip() == tumble.__version__


def test_it_imports_nothing_but_the_standard_library_numpy_and_protobuf():
    probe = ("import sys; before = set(sys.modules); import tumble, tumble.aio; "
             "print('\\n'.join(sorted(set(sys.modules) - before)))")
    done = subprocess.run([sys.executable, "-c", probe], check=True, capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": os.path.join(SOURCE, "src")})
    roots = {name.split(".")[0] for name in done.stdout.split()}
    stdlib = sys.stdlib_module_names
    foreign = sorted(r for r in roots if r not in stdlib and r not in {"tumble", "numpy", "google", "cython_runtime"}
                     and not r.startswith("_"))
    assert not foreign, f"the package imports {foreign}"


def public_names():
    for module in (tumble, tumble.aio):
        for name in module.__all__:
            obj = getattr(module, name)
            if name.startswith("__") or not (inspect.isclass(obj) or inspect.isfunction(obj)):
                continue  # type aliases (BodyLike, Vector) are documented where they are defined
            yield f"{module.__name__}.{name}", obj
            if inspect.isclass(obj):
                for member_name, member in vars(obj).items():
                    if member_name.startswith("_") or not (inspect.isfunction(member) or isinstance(member, property)):
                        continue
                    yield f"{module.__name__}.{name}.{member_name}", member


def test_every_public_name_has_a_docstring_and_type_hints():
    missing_docs = [name for name, obj in public_names() if not inspect.getdoc(obj)]
    assert not missing_docs, f"no docstring: {missing_docs}"
    unhinted = []
    for name, obj in public_names():
        function = obj.fget if isinstance(obj, property) else obj
        if inspect.isfunction(function):
            hints = function.__annotations__
            parameters = [p for p in inspect.signature(function).parameters if p not in ("self", "cls")]
            if "return" not in hints or any(p not in hints for p in parameters):
                unhinted.append(name)
    assert not unhinted, f"without type hints: {unhinted}"
