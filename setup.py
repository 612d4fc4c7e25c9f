"""Build the optional compiled kernels; all metadata is in ``pyproject.toml``.

Every ``*.pyx`` file under ``maxplus/`` and ``tegraph/`` becomes an extension
module of the same dotted name (``maxplus/_howard_kernel.pyx`` ->
``maxplus._howard_kernel``), compiled with the machine's C compiler within
``pip install .``. Each one is optional: where Cython or a compiler is missing,
or a module fails to compile, the install goes on and the module that would
have used it runs its pure Python/numpy path, which the suite tests too.
"""

from pathlib import Path

from setuptools import Extension, setup

HERE = Path(__file__).parent


def _extensions() -> list:
    try:
        from Cython.Build import cythonize
    except ImportError:  # built without isolation in an environment with no Cython
        return []
    sources = sorted(p.relative_to(HERE) for package in ("maxplus", "tegraph")
                     for p in (HERE / package).rglob("*.pyx"))
    modules = [Extension(".".join(source.with_suffix("").parts), [str(source)],
                         optional=True, extra_compile_args=["-O2"])
               for source in sources]
    return cythonize(modules, language_level=3, quiet=True,
                     compiler_directives={"boundscheck": False, "wraparound": False,
                                          "cdivision": True, "initializedcheck": False})


setup(ext_modules=_extensions())
