"""The reduced decision model of a release: P(t_stop, Delta, Dw) without ensembles.

* :mod:`.table`: :class:`DecisionTable`, the end-of-stop memory torque and escape law;
* :mod:`.runs`: the noise-free runs that measure a table;
* :mod:`.fit`: the noise intensity fitted to an ensemble;
* :mod:`.check`: the model against every point of stored sweep reports;
* :mod:`.goodness`: the aggregate test and the calibration of the model by bins;
* :mod:`.map`: the predicted Fig. 9 map, with ensemble points, and the master curve.
"""
