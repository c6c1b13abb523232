"""Files: run directories, atomic writes and the mp4 encoder.

* :mod:`.output`: the run directory layout and atomic file writing;
* :mod:`.mp4`: H.264 movies with the ffmpeg binary of imageio-ffmpeg.
"""
