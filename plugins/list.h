/* The one list of built-in effects, in the order `dtmap effects` prints
 * them. Each line names the const dtm_effect_class a plugin folder exports.
 * Include after defining DTM_EFFECT(symbol). */
DTM_EFFECT(dtm_effect_elastic)
DTM_EFFECT(dtm_effect_damping)
DTM_EFFECT(dtm_effect_thermal)
DTM_EFFECT(dtm_effect_hydraulic)
DTM_EFFECT(dtm_effect_cohesive)
