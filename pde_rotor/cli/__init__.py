"""The ``pde-rotor`` command line (typer).

* :mod:`.main`: the app and run, show, check, info;
* :mod:`.common`: exit codes, the one-line failure, shared options;
* :mod:`.sweep`: ``sweep`` and ``report``;
* :mod:`.plot`: ``plot`` (the figure of a sweep report);
* :mod:`.predict`: ``predict`` (the decision model);
* :mod:`.gallery`: ``gallery`` (the paper's figures);
* :mod:`.stability`: ``stability`` (rest state, eigenvalues and onsets of a config).
"""
