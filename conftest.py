"""pytest's configuration for the whole repository (``tests/conftest.py`` has the tests' own).

The kernels nbval starts for ``notebooks/`` talk over sockets in a private folder,
not TCP ports: ``tools/kernel_sockets.py`` says why (two kernels started at the same
moment by different processes can be handed the same port, and one dies before its
first cell; ``make test`` runs two workers and, for other machines, three nbval runs
at once). nbval builds its kernel manager from the name ``KernelManager`` in
``nbval.kernel``; that name is pointed at jupyter_client's manager with private
sockets, and nothing else of nbval changes.
"""

from __future__ import annotations

import nbval.kernel

from tools.kernel_sockets import PrivateSocketsKernelManager

nbval.kernel.KernelManager = PrivateSocketsKernelManager
