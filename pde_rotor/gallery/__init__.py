"""The paper's figures: running the gallery scripts and the library they share.

* :mod:`.runner`: run the scripts of the repository's gallery/ and publish their images.
"""
