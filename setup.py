"""Build the optional compiled kernels; all metadata is in ``pyproject.toml``.

Every ``*.pyx`` file under ``maxplus/`` and ``tegraph/`` becomes an extension
module of the same dotted name (``maxplus/_howard_kernel.pyx`` ->
``maxplus._howard_kernel``), compiled with the machine's C compiler within
``pip install .``. Each one is optional: where Cython or a compiler is missing,
or a module fails to compile, the install goes on and the module that would
have used it runs its pure Python/numpy path, which the suite tests too.
``tegraph --version`` says which are built; ``tests/test_compiled_kernels.py``
fails where a compiler and Cython were there and one is missing.
"""

import sys
from pathlib import Path

HERE = Path(__file__).parent


def extension_sources() -> dict[str, str]:
    """Every extension module this file builds: dotted name -> its ``.pyx`` (relative)."""
    sources = sorted(p.relative_to(HERE) for package in ("maxplus", "tegraph")
                     for p in (HERE / package).rglob("*.pyx"))
    return {".".join(source.with_suffix("").parts): str(source) for source in sources}


def _extensions() -> list:
    from setuptools import Extension

    try:
        from Cython.Build import cythonize
    except ImportError:  # built without isolation in an environment with no Cython
        print("warning: Cython is not installed: the compiled kernels are not built "
              "(pip install Cython, then python setup.py build_ext --inplace)", file=sys.stderr)
        return []
    modules = [Extension(name, [source], extra_compile_args=["-O2"])
               for name, source in extension_sources().items()]
    built = cythonize(modules, language_level=3, quiet=True,
                      compiler_directives={"boundscheck": False, "wraparound": False,
                                           "cdivision": True, "initializedcheck": False})
    for extension in built:  # set here: cythonize makes new Extensions without the flag
        extension.optional = True
    return built


if __name__ == "__main__":  # pip's build backend runs this file as __main__ too
    from setuptools import setup

    setup(ext_modules=_extensions())
