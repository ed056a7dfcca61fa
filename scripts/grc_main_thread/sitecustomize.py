# SPDX-License-Identifier: GPL-3.0-or-later
"""For scripts/check_installed_examples.sh's GNU Radio Companion check only (on PYTHONPATH there).

GNU Radio Companion 3.10.5 calls its block tree's update_docs when its docstring loader
finishes, from the loader's worker thread (gnuradio/grc/core/utils/extract_docs.py,
SubprocessLoader.run_worker -> callback_finished): GTK calls off the main thread. When the
loader finishes while the window draws, GTK can crash (a segfault in gtk_tree_store_set_value,
seen once under the sanitizers with other tests running beside it). This runs that callback on
GTK's main loop instead, as GTK requires; nothing else of GRC changes. It applies in the
gnuradio-companion process alone (this file is the interpreter's sitecustomize, so it sees every
Python process the check starts)."""
import os
import sys

if os.path.basename(sys.argv[0] if sys.argv else "") == "gnuradio-companion":
    from gi.repository import GLib
    from gnuradio.grc.core.utils import extract_docs

    _init = extract_docs.SubprocessLoader.__init__

    def _init_on_main_loop(self, callback_query_result, callback_finished=None):
        _init(self, callback_query_result, callback_finished)
        finished = self.callback_finished

        def on_main_loop():
            finished()
            return False  # once

        self.callback_finished = lambda: GLib.idle_add(on_main_loop)

    extract_docs.SubprocessLoader.__init__ = _init_on_main_loop
