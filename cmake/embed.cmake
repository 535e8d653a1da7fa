# Turn a text file into a C string constant (used for the scene XSD).
file(READ ${IN} content HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${content}")
file(WRITE ${OUT} "/* Generated from the scene schema; do not edit. */\n#include <stddef.h>\nconst unsigned char dtm_scene_xsd[] = {${bytes} 0x00};\nconst size_t dtm_scene_xsd_len = sizeof dtm_scene_xsd - 1;\n")
