"""Figures: a run's movie frames and summary, the shared figure helpers, the Fig. 9 map,
the figure of any sweep report.

* :mod:`.run`: movie frames and the summary figure of ``pde-rotor show``;
* :mod:`.figures`: pyplot-free figures, footers and probability axes of the gallery;
* :mod:`.decision_map`: the Fig. 9 map from the decision model with ensemble points;
* :mod:`.report`: P of any sweep report against its axis, or a heat map (``pde-rotor plot``).
"""
