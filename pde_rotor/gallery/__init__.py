"""The paper's figures: running the gallery scripts and the library they share.

* :mod:`.common`: fidelities (full, quick, tiny), paths, argument parsing and footers;
* :mod:`.sweeps`: the probability figures' sweeps, stored reports, crossings and the
  paper's stated values;
* :mod:`.timeseries`: the time-series figures (Figs. 4 and 6) and their stored runs;
* :mod:`.onsets`: the simulated onsets of motion of camphor bodies (free disk);
* :mod:`.runner`: run the scripts of the repository's gallery/ and publish their images.
"""
