"""Types of the compiled loop ``_engine_kernel_wide.pyx`` (for mypy, which reads no extension).

Both compiled loops include one ``_engine_loop.pxi``: the same interface, typed once in
``_engine_kernel.pyi``.
"""

from ._engine_kernel import Kernel as Kernel
from ._engine_kernel import covers as covers
