"""Inversion statistics: the inversion rule, proportions with intervals, crossings.

* :mod:`.inversion`: the one rule that decides whether a stop inverted the rotor;
* :mod:`.proportions`: Wilson intervals, the protocol and restart estimators, the
  two-state chain and the agreement test;
* :mod:`.crossing`: where a measured probability curve crosses a level, with an interval.
"""
