"""Message codecs, bags and live alike: per encoding (ros1, cdr, protobuf, json) the transform and
clock decoders, in bulk and for one message, the encoders tftools writes with, and the header parsers;
``types`` asks rosbags' type stores for definitions, ``select`` says which channels are read how."""
