"""Vision: camera images to percepts (DNT and NimbRo pipelines); see :mod:`.vision`.

>>> from cognition.vision import Vision, VisionParams
>>> percepts = Vision(VisionParams(method="dnt"), scheme="classic").detect(image, camera)  # doctest: +SKIP
"""

from cognition.vision.colour import Colour, ColourClassifier, ColourParams
from cognition.vision.image import VisionError, rgb_to_yuv422
from cognition.vision.params import METHODS, VisionParams
from cognition.vision.vision import Vision, VisionDebug

__all__ = [
    "METHODS",
    "Colour",
    "ColourClassifier",
    "ColourParams",
    "Vision",
    "VisionDebug",
    "VisionError",
    "VisionParams",
    "rgb_to_yuv422",
]
