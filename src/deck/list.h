/* The deck writers, one line each: DECK_WRITER(table), the table a writer
 * file exports (src/deck/<solver>.c). A new format is a new file and one
 * line here. Included twice by deck.c with its own DECK_WRITER. */
DECK_WRITER(dtm_deck_calculix)
DECK_WRITER(dtm_deck_abaqus)
DECK_WRITER(dtm_deck_lsdyna)
